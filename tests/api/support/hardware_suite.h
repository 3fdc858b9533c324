#pragma once

// A test suite against a robot's emulated devices: mobot-emulate ROBOT, and a mobotd
// --backend hardware on the config it wrote, for the whole suite.

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "support/api_test.h"
#include "support/emulator_process.h"

namespace mobot::testing {

class HardwareSuite : public ::testing::Test {
 protected:
  // `prepare` may edit the emulator's config (add a device) before mobotd reads it.
  static void start(const std::string& robot,
                    const std::function<void(const std::filesystem::path&)>& prepare = nullptr) {
    emulator_ = std::make_unique<EmulatorProcess>(robot);
    if (prepare) prepare(emulator_->config_path());
    MobotdProcess::Options options;
    options.backend = "hardware";
    options.time_scale = 1.0;  // real devices live in real time
    options.extra_args = {"--config", emulator_->config_path().string()};
    server_ = std::make_unique<MobotdProcess>(options);
  }
  static void TearDownTestSuite() {
    // A clean shutdown with the devices still talking: their threads must stop before what they
    // call into goes (a laser's scans are forwarded to the runtime on the laser's thread).
    if (server_ && server_->alive()) {
      EXPECT_EQ(server_->terminate(), 0) << "mobotd did not exit cleanly on SIGTERM";
    }
    server_.reset();
    emulator_.reset();
  }

  static HttpClient admin() { return {server_->port(), server_->token()}; }
  static bool all_sensors_ok() {
    const json state = robot_state(admin());
    if (!state.contains("sensors")) return false;
    for (const auto& [name, sensor] : state.at("sensors").items()) {
      if (!sensor.value("ok", false)) return false;
    }
    return true;
  }
  static json sensor(const std::string& name) {
    return robot_state(admin()).at("sensors").value(name, json::object());
  }

  static inline std::unique_ptr<EmulatorProcess> emulator_;
  static inline std::unique_ptr<MobotdProcess> server_;
};

}  // namespace mobot::testing
