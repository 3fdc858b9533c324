#include "server/config.h"
#include "server/plugins/plugins.h"

#include <gtest/gtest.h>
#include <filesystem>

#include "config_files.h"

namespace mobot::server {
namespace {

using test::load_error_of;
using test::write_config;

TEST(Config, TheShippedDefaultLoads) {
  const Config config =
      load_config(std::filesystem::path(MOBOT_SOURCE_ROOT) / "deploy/config/default.yaml");
  EXPECT_EQ(config.backend, "sim");
  EXPECT_DOUBLE_EQ(config.robot.control_rate_hz, 50.0);
  EXPECT_EQ(config.sim.world, "office");
  EXPECT_EQ(config.robot.mux_sources.size(), 4U);
}

TEST(Config, AnEmptyFileGivesTheDefaults) {
  const Config config = load_config(write_config(""));
  EXPECT_EQ(config.server.port, 8080);
  EXPECT_DOUBLE_EQ(config.robot.laser_rate_hz, 10.0);
}

TEST(Config, ReadsValues) {
  const Config config = load_config(write_config(
      "server: {port: 9000}\nrobot: {laser_rate_hz: 40}\nsim: {world: g2_lobby, seed: 7}\n"));
  EXPECT_EQ(config.server.port, 9000);
  EXPECT_DOUBLE_EQ(config.robot.laser_rate_hz, 40.0);
  EXPECT_EQ(config.sim.world, "g2_lobby");
  EXPECT_EQ(config.sim.seed, 7U);
}

TEST(Config, ReadsCalibratedOdometryAndTheFusedMeasurementSets) {
  const Config config = load_config(write_config(
      "odometry: {left_wheel_radius_m: 0.0747, right_wheel_radius_m: 0.0752, track_m: 0.606}\n"
      "localization: {method: ekf}\nestimators: {ekf: {fuse: [compass]}}\n"));
  EXPECT_DOUBLE_EQ(config.odometry.left_wheel_radius_m, 0.0747);
  EXPECT_DOUBLE_EQ(config.odometry.track_m, 0.606);
  // The EKF plugin reads its own section: compass on, lines and bearings off.
  const auto estimators = configure_plugins(builtin_plugins(), config, {}).estimators;
  EXPECT_EQ(estimators.make("ekf")->method(), "ekf(odometry+compass)");
  EXPECT_NE(load_error_of("estimators: {ekf: {fuse: [gps]}}").find("'gps'"), std::string::npos);
  EXPECT_NE(load_error_of("localization: {method: magic}").find("localization.method"),
            std::string::npos);
  EXPECT_NE(load_error_of("navigation: {max_linear_mps: 5}").find("navigation.max_linear_mps"),
            std::string::npos);
}

TEST(Config, MessagesNameTheKeyAndTheRange) {
  EXPECT_EQ(load_error_of("robot: {laser_rate_hz: 100}"),
            "robot.laser_rate_hz: 100 is outside the allowed range [1, 40]");
  EXPECT_EQ(load_error_of("server: {port: lots}"), "server.port: expected an integer");
  EXPECT_EQ(load_error_of("sim: {time_scale: 0}"),
            "sim.time_scale: 0 is outside the allowed range [0.1, 100]");
  EXPECT_NE(load_error_of("backend: cloud").find("backend: 'cloud'"), std::string::npos);
}

// The files themselves are looked at when the config is validated (after the flags): a path that
// cannot be read is refused with its key, before the server starts anything.
TEST(Config, TlsFilesThatCannotBeReadAreRefusedNamingTheKey) {
  const auto cert = write_config("not really a certificate");
  const auto key = write_config("not really a key");
  EXPECT_NO_THROW(load_config(
      write_config("server: {tls: {cert: " + cert.string() + ", key: " + key.string() + "}}\n")));
  const std::string missing = "/nonexistent/mobot/key.pem";
  const std::string message =
      load_error_of("server: {tls: {cert: " + cert.string() + ", key: " + missing + "}}\n");
  EXPECT_EQ(message.rfind("server.tls.key (--tls-key): cannot read " + missing, 0), 0U) << message;
  const std::string directory =
      load_error_of("server: {tls: {cert: /tmp, key: " + key.string() + "}}");
  EXPECT_NE(directory.find("server.tls.cert (--tls-cert): /tmp is a directory"), std::string::npos)
      << directory;
  // The flags go through the same check.
  Config config;
  config.server.tls_cert = cert;
  EXPECT_THROW(validate_config(config), ConfigError) << "a certificate without a key";
  config.server.tls_key = missing;
  EXPECT_THROW(validate_config(config), ConfigError);
  config.server.tls_key = key;
  EXPECT_NO_THROW(validate_config(config));
}

TEST(Config, MisspeltKeysAreRejected) {
  EXPECT_EQ(load_error_of("robot: {laser_rate: 20}"), "robot.laser_rate: unknown key");
  EXPECT_EQ(load_error_of("robots: {}"), "robots: unknown key");
}

TEST(Config, TheMuxNeedsSafetyAndTeleop) {
  EXPECT_NE(load_error_of("mux: [{name: teleop, priority: 7, timeout_s: 1}]").find("'safety'"),
            std::string::npos);
  EXPECT_NE(load_error_of("mux: [{name: teleop}]").find("mux[0]"), std::string::npos);
}

TEST(Config, UnreadableAndMalformedFilesAreReported) {
  EXPECT_THROW(load_config("/nonexistent/mobot.yaml"), ConfigError);
  EXPECT_THROW(load_config(write_config("server: [unclosed")), ConfigError);
  EXPECT_THROW(load_config(write_config("- a list")), ConfigError);
}

}  // namespace
}  // namespace mobot::server
