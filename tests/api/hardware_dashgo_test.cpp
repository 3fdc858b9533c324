// mobotd --backend hardware driving the Dashgo D1's emulated devices (mobot-emulate dashgo) over
// pseudo-terminals: the real drivers, protocols and fault handling, without the robot.
#include <dirent.h>

#include <sstream>

#include "support/api_test.h"
#include "support/emulator_process.h"

namespace mobot::testing {
namespace {

struct EmulatedPose {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;
};

int open_fds(pid_t pid) {
  int count = 0;
  DIR* dir = ::opendir(("/proc/" + std::to_string(pid) + "/fd").c_str());
  if (dir == nullptr) return -1;
  while (::readdir(dir) != nullptr) ++count;
  ::closedir(dir);
  return count;
}

class HardwareDashgoTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    emulator_ = std::make_unique<EmulatorProcess>("dashgo");
    MobotdProcess::Options options;
    options.backend = "hardware";
    options.time_scale = 1.0;
    options.extra_args = {"--config", emulator_->config_path().string()};
    server_ = std::make_unique<MobotdProcess>(options);
  }
  static void TearDownTestSuite() {
    server_.reset();
    emulator_.reset();
  }
  void SetUp() override {
    ASSERT_TRUE(server_->alive());
    // Each test starts with every device answering and the e-stop released.
    ASSERT_TRUE(wait_until([] { return all_sensors_ok(); }, 10s)) << robot_state(admin()).dump();
    admin().post("/api/v1/estop", json{{"engaged", false}});
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
  static EmulatedPose emulated_pose() {
    std::istringstream in(emulator_->command("pose"));
    std::string word;
    EmulatedPose pose;
    in >> word >> pose.x >> pose.y >> pose.theta;
    return pose;
  }
  // The base's wheel set-points as the emulated Arduino last received them.
  static std::pair<double, double> wheel_setpoints() {
    std::istringstream in(emulator_->command("wheels"));
    std::string word;
    std::pair<double, double> wheels{std::nan(""), std::nan("")};
    in >> word >> wheels.first >> wheels.second;
    return wheels;
  }

  static inline std::unique_ptr<EmulatorProcess> emulator_;
  static inline std::unique_ptr<MobotdProcess> server_;
};

TEST_F(HardwareDashgoTest, EveryDeviceAnswersAndShowsOnMetrics) {
  const json state = robot_state(admin());
  for (const char* name : {"encoders", "sonar", "ir"}) {
    ASSERT_TRUE(state.at("sensors").contains(name)) << state.dump();
    EXPECT_TRUE(state.at("sensors").at(name).at("ok").get<bool>()) << name;
  }
  const std::string metrics = admin().get("/metrics").body;
  EXPECT_NE(metrics.find("mobot_device_ok{device=\"base\"} 1"), std::string::npos) << metrics;
  EXPECT_NE(metrics.find("mobot_device_ok{device=\"ir\"} 1"), std::string::npos);
  EXPECT_NE(metrics.find("mobot_device_bytes_total{device=\"base\"}"), std::string::npos);
}

TEST_F(HardwareDashgoTest, TeleopTurnsTheWheelsAndTheOdometryFollows) {
  const EmulatedPose start = emulated_pose();
  const json pose_before = robot_state(admin()).at("pose");
  drive_for(admin(), 0.2, 0.0, 2.0);
  ASSERT_TRUE(wait_until([] { return wheel_setpoints().first == 0.0; }, 3s));
  const EmulatedPose end = emulated_pose();
  const double moved_m = std::hypot(end.x - start.x, end.y - start.y);
  EXPECT_GT(moved_m, 0.25);
  const json pose_after = robot_state(admin()).at("pose");
  const double odometry_m =
      std::hypot(pose_after.at("x").get<double>() - pose_before.at("x").get<double>(),
                 pose_after.at("y").get<double>() - pose_before.at("y").get<double>());
  // The odometry counts what the wheels turned; the emulated wheels' PID holds 2 %.
  EXPECT_NEAR(odometry_m, moved_m, 0.1 * moved_m);
}

TEST_F(HardwareDashgoTest, EachFaultOfTheIrBoardStopsTheRobotAndRecovers) {
  for (const std::string fault : {"unplug", "drop", "stall", "garbage", "checksum"}) {
    SCOPED_TRACE(fault);
    ASSERT_TRUE(wait_until([] { return all_sensors_ok(); }, 10s));
    // Keep driving through the fault: the safety layer must win over the operator.
    std::atomic<bool> stop{false};
    std::thread driver([&] { drive_for(admin(), 0.1, 0.0, 30.0, [&] { return stop.load(); }); });
    ASSERT_TRUE(wait_until([] { return wheel_setpoints().first > 0.0; }, 3s));
    ASSERT_EQ(emulator_->command("fault ir " + fault), "ok");
    ASSERT_TRUE(wait_until([] { return !sensor("ir").value("ok", true); }, 3s));
    const auto seen = std::chrono::steady_clock::now();
    EXPECT_TRUE(wait_until([] { return wheel_setpoints().first == 0.0; }, 1s));
    const double stop_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - seen).count();
    // The base's own cycle (20 ms) carries the zero set-point; the poll of /robot adds its own.
    EXPECT_LT(stop_ms, 200.0);
    EXPECT_FALSE(sensor("ir").value("reason", "").empty());
    const json event = find_event(admin(), current_run_id(admin()), "fault");
    ASSERT_FALSE(event.is_null());
    EXPECT_EQ(event.at("detail").at("sensor"), "ir");
    stop = true;
    driver.join();
    ASSERT_EQ(emulator_->command("clear ir"), "ok");
    EXPECT_TRUE(wait_until([] { return sensor("ir").value("ok", false); }, 5s))
        << sensor("ir").dump();
  }
}

TEST_F(HardwareDashgoTest, ABaseThatVanishesIsMissingAndComesBackByItself) {
  ASSERT_EQ(emulator_->command("fault base unplug"), "ok");
  ASSERT_TRUE(wait_until([] { return !sensor("encoders").value("ok", true); }, 2s));
  EXPECT_EQ(sensor("encoders").value("reason", ""), "missing");
  ASSERT_EQ(emulator_->command("clear base"), "ok");
  EXPECT_TRUE(wait_until([] { return sensor("encoders").value("ok", false); }, 5s));
  const std::string metrics = admin().get("/metrics").body;
  EXPECT_EQ(metrics.find("mobot_device_reconnects_total{device=\"base\"} 0"), std::string::npos);
}

TEST_F(HardwareDashgoTest, TheBaseButtonEngagesTheEstop) {
  ASSERT_EQ(emulator_->command("estop on"), "ok");
  ASSERT_TRUE(wait_until([] { return robot_state(admin()).value("estop", false); }, 2s));
  EXPECT_EQ(admin().post("/api/v1/teleop", json{{"v", 0.1}, {"w", 0.0}}).status, 409);
  // Held down, the button keeps it engaged.
  admin().post("/api/v1/estop", json{{"engaged", false}});
  EXPECT_TRUE(robot_state(admin()).value("estop", false));
  const json event = find_event(admin(), current_run_id(admin()), "estop");
  ASSERT_FALSE(event.is_null());
  EXPECT_EQ(event.at("detail").value("source", ""), "button");
  ASSERT_EQ(emulator_->command("estop off"), "ok");
  ASSERT_TRUE(wait_until(
      [] {
        admin().post("/api/v1/estop", json{{"engaged", false}});
        return !robot_state(admin()).value("estop", true);
      },
      2s));
}

TEST_F(HardwareDashgoTest, FiftyUnplugsCrashNothingAndLeakNoFileDescriptor) {
  const int before = open_fds(server_->pid());
  ASSERT_GT(before, 0);
  for (int i = 0; i < 50; ++i) {
    ASSERT_EQ(emulator_->command("fault ir unplug"), "ok");
    ASSERT_TRUE(wait_until([] { return !sensor("ir").value("ok", true); }, 2s)) << i;
    ASSERT_EQ(emulator_->command("clear ir"), "ok");
    ASSERT_TRUE(wait_until([] { return sensor("ir").value("ok", false); }, 5s)) << i;
  }
  EXPECT_TRUE(server_->alive());
  // A leak grows with the cycles; a socket of the last request may still be closing.
  EXPECT_TRUE(wait_until([&] { return open_fds(server_->pid()) <= before; }, 3s))
      << open_fds(server_->pid()) << " open, " << before << " before";
}

}  // namespace
}  // namespace mobot::testing
