// deploy/config/dashgo_d1.yaml loads as the Dashgo D1 (docs/algorithms.md R2), and the
// simulator's odometry errors (sim.odometry) are read, checked and passed on.
#include <gtest/gtest.h>

#include <filesystem>

#include "config_files.h"
#include "server/config.h"

namespace mobot::server {
namespace {

using test::load_error_of;
using test::write_config;

TEST(DashgoConfig, TheShippedFileLoadsWithTheR2Numbers) {
  const Config config =
      load_config(std::filesystem::path(MOBOT_SOURCE_ROOT) / "deploy/config/dashgo_d1.yaml");
  EXPECT_EQ(config.robot.profile, "dashgo_d1");
  EXPECT_DOUBLE_EQ(config.robot.laser_rate_hz, 7.0);
  EXPECT_DOUBLE_EQ(config.robot.limits.max_linear_mps, 0.5);
  EXPECT_DOUBLE_EQ(config.robot.limits.max_angular_radps, 0.7);
  EXPECT_DOUBLE_EQ(config.robot.limits.max_linear_accel_mps2, 0.3);
  EXPECT_DOUBLE_EQ(config.robot.limits.max_angular_accel_radps2, 0.3);
  ASSERT_EQ(config.robot.mux_sources.size(), 4U);
  EXPECT_EQ(config.robot.mux_sources[1].name, "ir_safety");
  EXPECT_EQ(config.robot.mux_sources[1].priority, 9);
  EXPECT_DOUBLE_EQ(config.robot.mux_sources[1].timeout_s, 0.5);
  EXPECT_DOUBLE_EQ(config.navigation.inscribed_radius_m, 0.22);
  EXPECT_LE(config.navigation.max_linear_mps, config.robot.limits.max_linear_mps);
  EXPECT_EQ(config.sim.odometry.scale_error, 0.01);
  EXPECT_EQ(config.sim.odometry.heading_drift_rad_per_m, 0.004);
  EXPECT_EQ(config.sim.odometry.step_noise_fraction, 0.03);
}

TEST(DashgoConfig, SimOdometryKeysAreOptionalAndUnsetMeansTheProfiles) {
  Config config = load_config(write_config("sim: {odometry: {scale_error: -0.02}}\n"));
  EXPECT_EQ(config.sim.odometry.scale_error, -0.02);
  EXPECT_FALSE(config.sim.odometry.heading_drift_rad_per_m);
  EXPECT_FALSE(config.sim.odometry.step_noise_fraction);
  EXPECT_TRUE(config.sim.odometry.any());
  config = load_config(write_config("sim: {world: office}\n"));
  EXPECT_FALSE(config.sim.odometry.any());
  config = load_config(write_config("sim:\n  odometry:\n"));
  EXPECT_FALSE(config.sim.odometry.any()) << "an empty mapping";
}

TEST(DashgoConfig, BadSimOdometryNamesTheKey) {
  EXPECT_EQ(load_error_of("sim: {odometry: {scale: 0.01}}\n"), "sim.odometry.scale: unknown key");
  EXPECT_EQ(load_error_of("sim: {odometry: 0.01}\n"), "sim.odometry: expected a mapping");
  EXPECT_EQ(load_error_of("sim: {odometry: {scale_error: lots}}\n"),
            "sim.odometry.scale_error: expected a number");
  EXPECT_NE(load_error_of("sim: {odometry: {scale_error: 0.5}}\n").find("sim.odometry.scale_error"),
            std::string::npos);
  EXPECT_NE(load_error_of("sim: {odometry: {step_noise_fraction: -0.1}}\n")
                .find("outside the allowed range"),
            std::string::npos);
  EXPECT_NE(load_error_of("sim: {odometry: {heading_drift_rad_per_m: .nan}}\n")
                .find("sim.odometry.heading_drift_rad_per_m"),
            std::string::npos);
}

}  // namespace
}  // namespace mobot::server
