#include "server/config.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

#include "server/config_parser.h"
#include "server/plugins/plugins.h"

namespace mobot::server {

Config load_config(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ConfigError(file.string() + ": cannot read the config file");
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  Config config = parse_config(text, file.string());
  validate_config(config);
  return config;
}

namespace {

// The TLS files are read when the server starts listening, after the robot is up: a path that
// cannot be read is refused here, at once, with the key that named it.
void check_readable(const std::filesystem::path& file, const std::string& key,
                    const std::string& flag) {
  if (file.empty()) return;
  std::error_code error;
  if (std::filesystem::is_directory(file, error)) {
    throw ConfigError(key + " (" + flag + "): " + file.string() + " is a directory, not a file");
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    throw ConfigError(key + " (" + flag + "): cannot read " + file.string() + ": " +
                      std::strerror(errno));
  }
}

}  // namespace

void validate_config(const Config& config) {
  check_config_rules(config);
  check_readable(config.server.tls_cert, "server.tls.cert", "--tls-cert");
  check_readable(config.server.tls_key, "server.tls.key", "--tls-key");
  // The names the config selects and every plugin's own section; the geometry only matters
  // when instances are made.
  try {
    configure_plugins(builtin_plugins(), config, kinematics::RobotGeometry{});
  } catch (const YAML::Exception& error) {
    // A node of a shape no plugin reader expected (a list as a key, say): a config error with the
    // node's line and column, not an exception that ends mobotd unexplained.
    throw ConfigError(std::string("plugin options: ") + error.what());
  }
}

}  // namespace mobot::server
