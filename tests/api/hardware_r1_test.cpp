// mobotd --backend hardware driving R1's emulated devices (mobot-emulate r1): the Motion Mind
// wheel and tilt boards on one line, the SICK LMS2xx, and the Modbus RTU sensor bus.
#include <sstream>

#include "support/api_test.h"
#include "support/hardware_suite.h"

namespace mobot::testing {
namespace {

class HardwareR1Test : public HardwareSuite {
 protected:
  static void SetUpTestSuite() { start("r1"); }
  void SetUp() override {
    ASSERT_TRUE(server_->alive());
    ASSERT_TRUE(wait_until([] { return all_sensors_ok(); }, 15s)) << robot_state(admin()).dump();
  }

  static std::pair<double, double> emulated_xy() {
    std::istringstream in(emulator_->command("pose"));
    std::string word;
    std::pair<double, double> xy;
    in >> word >> xy.first >> xy.second;
    return xy;
  }
};

TEST_F(HardwareR1Test, EveryDeviceAnswers) {
  const json sensors = robot_state(admin()).at("sensors");
  for (const char* name : {"encoders", "laser", "sonar", "compass"}) {
    ASSERT_TRUE(sensors.contains(name)) << sensors.dump();
    EXPECT_TRUE(sensors.at(name).at("ok").get<bool>()) << name;
  }
  // The LMS at 500 kbaud and 0.5 deg: every other turn of its 75 Hz mirror (the rate is measured
  // over the last second, which may still hold the set-up).
  EXPECT_TRUE(
      wait_until([] { return std::abs(sensor("laser").value("rate_hz", 0.0) - 37.5) < 4.0; }, 5s))
      << sensor("laser").dump();
  const std::string metrics = admin().get("/metrics").body;
  for (const char* device : {"base", "laser", "bus"}) {
    EXPECT_NE(metrics.find("mobot_device_ok{device=\"" + std::string(device) + "\"} 1"),
              std::string::npos)
        << device;
  }
}

TEST_F(HardwareR1Test, TeleopTurnsTheMotionMindWheels) {
  const auto start = emulated_xy();
  const json pose_before = robot_state(admin()).at("pose");
  drive_for(admin(), 0.3, 0.0, 2.0);
  ASSERT_TRUE(wait_robot_time(admin(), 1.0));
  const auto end = emulated_xy();
  const double moved_m = std::hypot(end.first - start.first, end.second - start.second);
  EXPECT_GT(moved_m, 0.3);
  const json pose_after = robot_state(admin()).at("pose");
  const double estimated_m =
      std::hypot(pose_after.at("x").get<double>() - pose_before.at("x").get<double>(),
                 pose_after.at("y").get<double>() - pose_before.at("y").get<double>());
  EXPECT_NEAR(estimated_m, moved_m, 0.15 * moved_m);
}

TEST_F(HardwareR1Test, ASweepOfTheTiltAxisMakesACloud) {
  const HttpReply started = admin().post("/api/v1/sweeps", json{{"period_s", 10}, {"step_deg", 1}});
  ASSERT_EQ(started.status, 201) << started.body;
  const auto id = started.json().at("id").get<std::int64_t>();
  json sweep;
  ASSERT_TRUE(wait_until(
      [&] {
        sweep = admin().get("/api/v1/sweeps/" + std::to_string(id)).json();
        return sweep.at("status") != "running";
      },
      60s));
  EXPECT_EQ(sweep.at("status"), "done") << sweep.dump();
  EXPECT_GT(sweep.value("points", 0), 1000) << sweep.dump();
}

TEST_F(HardwareR1Test, ASonarNodeThatStopsAnsweringStopsTheRobotUntilItAnswers) {
  ASSERT_EQ(emulator_->command("node 4 off"), "ok");
  ASSERT_TRUE(wait_until([] { return !sensor("sonar").value("ok", true); }, 5s));
  EXPECT_FALSE(sensor("sonar").value("reason", "").empty());
  EXPECT_EQ(admin().post("/api/v1/teleop", json{{"v", 0.2}, {"w", 0.0}}).status, 200);
  ASSERT_TRUE(wait_robot_time(admin(), 0.5));
  EXPECT_EQ(robot_state(admin()).at("velocity").at("v").get<double>(), 0.0);
  ASSERT_EQ(emulator_->command("node 4 on"), "ok");
  EXPECT_TRUE(wait_until([] { return sensor("sonar").value("ok", false); }, 5s))
      << sensor("sonar").dump();
}

}  // namespace
}  // namespace mobot::testing
