// The config's text to a Config (server/config_parser.cpp), as tests/fuzz/config_yaml_fuzz.cpp
// drives it: a config or a ConfigError, never another exception.
#include "server/config_parser.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace mobot::server {
namespace {

std::string rule_error_of(const std::string& text) {
  try {
    check_config_rules(parse_config(text, "test.yaml"));
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "<no error>";
}

TEST(ConfigParser, ReadsTextWithoutAFile) {
  const Config config =
      parse_config("robot: {control_rate_hz: 40}\nsim: {world: yard}\n", "inline");
  EXPECT_DOUBLE_EQ(config.robot.control_rate_hz, 40.0);
  EXPECT_EQ(config.sim.world, "yard");
  EXPECT_NO_THROW(check_config_rules(config));
  EXPECT_EQ(parse_config("", "empty").sim.world, "office") << "empty text: the defaults";
}

TEST(ConfigParser, KeysThatAreNotNamesAreConfigErrors) {
  // Found with tests/fuzz/config_yaml_fuzz.cpp's target: each ended mobotd with an uncaught
  // YAML::TypedBadConversion.
  EXPECT_NE(rule_error_of("{[a]: 1}").find("the top level: keys are plain names"),
            std::string::npos);
  EXPECT_NE(rule_error_of("robot: {[k]: 1}").find("robot: keys are plain names"),
            std::string::npos);
  EXPECT_NE(rule_error_of("sim:\n  odometry:\n    {x: 1}: 2\n").find("sim.odometry"),
            std::string::npos);
}

TEST(ConfigParser, MalformedYamlNamesTheSource) {
  EXPECT_EQ(rule_error_of("server: [unclosed").rfind("test.yaml: ", 0), 0U);
  EXPECT_NE(rule_error_of("- a list").find("expected a mapping at the top level"),
            std::string::npos);
}

TEST(ConfigParser, APluginSectionWithAListAsAKeyIsAConfigError) {
  const auto file = std::filesystem::temp_directory_path() /
                    ("mobot_config_parser_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(file) << "planners: {[astar]: {}}\n";
  EXPECT_THROW(load_config(file), ConfigError);
  std::filesystem::remove(file);
}

TEST(ConfigParser, ReadsTheTlsFilesAndRefusesHalfOfThem) {
  const Config config =
      parse_config("server: {tls: {cert: /etc/mobot/cert.pem, key: /etc/mobot/key.pem}}\n", "t");
  EXPECT_EQ(config.server.tls_cert, "/etc/mobot/cert.pem");
  EXPECT_EQ(config.server.tls_key, "/etc/mobot/key.pem");
  EXPECT_TRUE(config.server.tls());
  EXPECT_NO_THROW(check_config_rules(config));
  EXPECT_FALSE(parse_config("server: {port: 9000}\n", "t").server.tls()) << "no TLS by default";
  EXPECT_FALSE(parse_config("server: {tls: null}\n", "t").server.tls());

  EXPECT_NE(rule_error_of("server: {tls: {cert: a.pem}}").find("server.tls.key: missing"),
            std::string::npos);
  EXPECT_NE(rule_error_of("server: {tls: {key: a.key}}").find("server.tls.cert: missing"),
            std::string::npos);
  EXPECT_EQ(rule_error_of("server: {tls: {cert: a.pem, key: b.key, ca: c.pem}}"),
            "server.tls.ca: unknown key");
  EXPECT_EQ(rule_error_of("server: {tls: on}"),
            "server.tls: expected a mapping {cert: PATH, key: PATH}");
  EXPECT_EQ(rule_error_of("server: {tls: {cert: [a], key: b}}"),
            "server.tls.cert: expected a file path");
  EXPECT_EQ(rule_error_of("server: {tls: {cert: '', key: b}}"),
            "server.tls.cert: expected a file path");
  EXPECT_NE(rule_error_of("server: {tls: {[cert]: a}}").find("server.tls: keys are plain names"),
            std::string::npos);
}

}  // namespace
}  // namespace mobot::server
