#include "server/config.h"

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

void validate_config(const Config& config) {
  check_config_rules(config);
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
