// The config's slam section: every key reaches the SLAM and the map renderer, a bad one is refused
// with its full key.
#include "server/plugins/slam_options.h"

#include <gtest/gtest.h>

#include <string>

#include "server/plugins/option_reader.h"

namespace mobot::server {
namespace {

std::string slam_error_of(const std::string& yaml) {
  try {
    read_slam_options(YAML::Load(yaml));
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "";
}

TEST(SlamOptions, WithoutASectionTheDefaultsHold) {
  const SlamWorkerOptions options = read_slam_options(YAML::Load("robot: {}"));
  const slam::GraphSlamOptions defaults;
  EXPECT_EQ(options.slam.max_range_m, defaults.max_range_m);
  EXPECT_EQ(options.slam.match_covariance_scale, defaults.match_covariance_scale);
  EXPECT_EQ(options.render.resolution_m, defaults.resolution_m);
  EXPECT_DOUBLE_EQ(options.render.align_m, 64 * defaults.resolution_m);
}

TEST(SlamOptions, EveryKeyReachesTheSlamAndTheRenderer) {
  const SlamWorkerOptions options = read_slam_options(YAML::Load(R"(
slam:
  max_range_m: 12.0
  min_travel_m: 0.3
  min_rotation_rad: 0.4
  resolution_m: 0.1
  loop_search_radius_m: 6.0
  loop_min_score: 0.6
  match_covariance_scale: 0.5
  loop_covariance_scale: 8.0
  odom_translation_sigma_per_m: 0.05
  odom_rotation_sigma_per_rad: 0.04
  odom_rotation_sigma_per_m: 0.02
  match_field_sigma_m: 0.04
  local_map_spacing_m: 0.5
  map_period_s: 2.0
)"));
  EXPECT_EQ(options.slam.max_range_m, 12.0);
  EXPECT_EQ(options.slam.min_travel_m, 0.3);
  EXPECT_EQ(options.slam.min_rotation_rad, 0.4);
  EXPECT_EQ(options.slam.resolution_m, 0.1);
  EXPECT_EQ(options.slam.loop_search_radius_m, 6.0);
  EXPECT_EQ(options.slam.loop_min_score, 0.6);
  EXPECT_EQ(options.slam.match_covariance_scale, 0.5);
  EXPECT_EQ(options.slam.loop_covariance_scale, 8.0);
  EXPECT_EQ(options.slam.odom_translation_sigma_per_m, 0.05);
  EXPECT_EQ(options.slam.odom_rotation_sigma_per_rad, 0.04);
  EXPECT_EQ(options.slam.odom_rotation_sigma_per_m, 0.02);
  EXPECT_EQ(options.slam.match_field_sigma_m, 0.04);
  EXPECT_EQ(options.slam.local_map_spacing_m, 0.5);
  EXPECT_EQ(options.map_period_s, 2.0);
  EXPECT_EQ(options.render.resolution_m, 0.1);
  EXPECT_EQ(options.render.max_range_m, 12.0);
  EXPECT_DOUBLE_EQ(options.render.align_m, 6.4);
}

TEST(SlamOptions, TheMapMayBeDrawnWithAShorterRangeThanTheMatcherUses) {
  const SlamWorkerOptions options =
      read_slam_options(YAML::Load("slam: {max_range_m: 15.5, map_max_range_m: 8.0}"));
  EXPECT_EQ(options.slam.max_range_m, 15.5);
  EXPECT_EQ(options.render.max_range_m, 8.0);
  EXPECT_NE(slam_error_of("slam: {map_max_range_m: 0}").find("slam.map_max_range_m"),
            std::string::npos);
  EXPECT_NE(slam_error_of("slam: {local_map_spacing_m: -1}").find("slam.local_map_spacing_m"),
            std::string::npos);
}

TEST(SlamOptions, ABadValueIsRefusedWithItsKey) {
  EXPECT_NE(slam_error_of("slam: {max_range_m: 0.5}").find("slam.max_range_m"), std::string::npos);
  EXPECT_NE(slam_error_of("slam: {match_covariance_scale: 0}").find("slam.match_covariance_scale"),
            std::string::npos);
  EXPECT_NE(
      slam_error_of("slam: {odom_rotation_sigma_per_m: .nan}").find("slam.odom_rotation_sigma"),
      std::string::npos);
  EXPECT_NE(slam_error_of("slam: {resolution_m: fine}").find("slam.resolution_m"),
            std::string::npos);
  EXPECT_NE(slam_error_of("slam: {submap_size: 3}").find("slam.submap_size"), std::string::npos)
      << "an unknown key is refused";
  EXPECT_EQ(slam_error_of("slam: {max_range_m: 8.0}"), "");
}

}  // namespace
}  // namespace mobot::server
