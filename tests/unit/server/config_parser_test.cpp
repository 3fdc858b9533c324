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

std::string error_of(const std::string& text) {
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
  EXPECT_NE(error_of("{[a]: 1}").find("the top level: keys are plain names"), std::string::npos);
  EXPECT_NE(error_of("robot: {[k]: 1}").find("robot: keys are plain names"), std::string::npos);
  EXPECT_NE(error_of("sim:\n  odometry:\n    {x: 1}: 2\n").find("sim.odometry"), std::string::npos);
}

TEST(ConfigParser, MalformedYamlNamesTheSource) {
  EXPECT_EQ(error_of("server: [unclosed").rfind("test.yaml: ", 0), 0U);
  EXPECT_NE(error_of("- a list").find("expected a mapping at the top level"), std::string::npos);
}

TEST(ConfigParser, APluginSectionWithAListAsAKeyIsAConfigError) {
  const auto file = std::filesystem::temp_directory_path() /
                    ("mobot_config_parser_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(file) << "planners: {[astar]: {}}\n";
  EXPECT_THROW(load_config(file), ConfigError);
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace mobot::server
