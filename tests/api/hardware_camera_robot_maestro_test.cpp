// mobotd --backend hardware driving the camera robot's emulated devices (mobot-emulate
// camera_robot): the Dashgo's Arduino base and lidar, the camera head's Pololu Maestro (two servos
// and the ultrasonic ranger on an analog input) over a pseudo-terminal, and the camera playing
// the still frames the emulator wrote (a red ball at the image centre).
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "support/api_test.h"
#include "support/hardware_suite.h"

namespace mobot::testing {
namespace {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;
// One quarter-microsecond of the emulated servos (1000 us per 90 deg), and a few of them.
constexpr double kJointTolerance_rad = 0.002;

struct EmulatedHead {
  std::optional<double> pan_rad;
  std::optional<double> tilt_rad;
};

std::optional<double> number_or_none(const std::string& word) {
  if (word.empty() || word == "none") return std::nullopt;
  return std::stod(word);
}

class HardwareCameraRobotTest : public HardwareSuite {
 protected:
  // The emulator writes the camera's frames and puts them in the config as its source.
  static void SetUpTestSuite() { start("camera_robot"); }
  void SetUp() override {
    ASSERT_TRUE(server_->alive());
    ASSERT_TRUE(wait_until([] { return all_sensors_ok() && device_ok("pan_tilt"); }, 15s))
        << robot_state(admin()).dump() << admin().get("/metrics").body;
  }

  static bool device_ok(const std::string& device) {
    return admin().get("/metrics").body.find("mobot_device_ok{device=\"" + device + "\"} 1") !=
           std::string::npos;
  }
  static bool device_down(const std::string& device) {
    return admin().get("/metrics").body.find("mobot_device_ok{device=\"" + device + "\"} 0") !=
           std::string::npos;
  }
  // Where the emulated Maestro's servos are, through their calibration.
  static EmulatedHead emulated_head() {
    std::istringstream in(emulator_->command("maestro head"));
    std::string word;
    std::string pan;
    std::string tilt;
    in >> word >> pan >> tilt;
    return {number_or_none(pan), number_or_none(tilt)};
  }
  // What the emulated ranger sees now.
  static std::optional<double> emulated_range_m() {
    std::istringstream in(emulator_->command("maestro range"));
    std::string word;
    std::string range;
    in >> word >> range;
    return number_or_none(range);
  }
  static json camera() {
    const HttpReply reply = admin().get("/api/v1/camera");
    EXPECT_EQ(reply.status, 200) << reply.body;
    return reply.status == 200 ? reply.json() : json::object();
  }
  static bool head_at(double pan_rad, double tilt_rad) {
    const EmulatedHead head = emulated_head();
    return head.pan_rad && head.tilt_rad &&
           std::abs(*head.pan_rad - pan_rad) < kJointTolerance_rad &&
           std::abs(*head.tilt_rad - tilt_rad) < kJointTolerance_rad;
  }
  static void look(double pan_rad, double tilt_rad) {
    const HttpReply reply =
        admin().put("/api/v1/camera/pan_tilt", json{{"pan", pan_rad}, {"tilt", tilt_rad}});
    ASSERT_EQ(reply.status, 200) << reply.body;
    ASSERT_TRUE(wait_until([&] { return head_at(pan_rad, tilt_rad); }, 5s));
  }
};

TEST_F(HardwareCameraRobotTest, EveryDeviceAnswersAndTheCameraIsAPanTiltCamera) {
  const json sensors = robot_state(admin()).at("sensors");
  for (const char* name : {"encoders", "laser", "sonar"}) {
    ASSERT_TRUE(sensors.contains(name)) << sensors.dump();
    EXPECT_TRUE(sensors.at(name).at("ok").get<bool>()) << name;
  }
  for (const char* device : {"base", "laser", "camera", "pan_tilt"}) {
    EXPECT_TRUE(device_ok(device)) << device;
  }
  const json description = camera();
  EXPECT_EQ(description.at("kind"), "pan_tilt");
  EXPECT_EQ(description.at("width"), 640);
  EXPECT_EQ(description.at("height"), 480);
  EXPECT_DOUBLE_EQ(description.at("rate_hz").get<double>(), 15.0);
  // The limits of deploy/config/camera_robot_hardware.yaml: the hobby servos' +/-90 deg of pan.
  ASSERT_EQ(description.at("pan_limits").size(), 2U);
  EXPECT_NEAR(description.at("pan_limits")[0].get<double>(), -90.0 * kRadPerDeg, 1e-9);
  EXPECT_NEAR(description.at("pan_limits")[1].get<double>(), 90.0 * kRadPerDeg, 1e-9);
  EXPECT_NEAR(description.at("tilt_limits")[0].get<double>(), -30.0 * kRadPerDeg, 1e-9);
  EXPECT_NEAR(description.at("tilt_limits")[1].get<double>(), 45.0 * kRadPerDeg, 1e-9);
  EXPECT_TRUE(description.contains("pan"));
  EXPECT_TRUE(description.contains("tilt"));
  // Frames of the camera the head turns.
  ASSERT_TRUE(wait_until([] { return admin().get("/api/v1/camera/snapshot").status == 200; }, 5s));
}

TEST_F(HardwareCameraRobotTest, PanTiltMovesTheServosAndTheCameraReportsThemConverging) {
  look(0.0, 0.0);
  const HttpReply reply = admin().put("/api/v1/camera/pan_tilt", json{{"pan", 1.2}, {"tilt", 0.4}});
  ASSERT_EQ(reply.status, 200) << reply.body;
  EXPECT_DOUBLE_EQ(reply.json().at("pan").get<double>(), 1.2);
  EXPECT_DOUBLE_EQ(reply.json().at("tilt").get<double>(), 0.4);
  // The Maestro slews at the head's 2 rad/s (its speed 50: 1.96 rad/s): 1.2 rad take 0.6 s, and
  // GET /camera reports the pulses it reads back, on the way and at the end.
  std::vector<double> pans;
  ASSERT_TRUE(wait_until(
      [&] {
        pans.push_back(camera().value("pan", 0.0));
        return std::abs(pans.back() - 1.2) < kJointTolerance_rad;
      },
      5s, 10ms));
  const auto between =
      std::count_if(pans.begin(), pans.end(), [](double pan) { return pan > 0.05 && pan < 1.15; });
  EXPECT_GE(between, 3) << "no angle on the way was reported";
  for (std::size_t i = 1; i < pans.size(); ++i) EXPECT_GE(pans[i], pans[i - 1] - 1e-9);
  EXPECT_TRUE(wait_until([] { return std::abs(camera().value("tilt", 0.0) - 0.4) < 0.002; }, 2s));
  EXPECT_TRUE(head_at(1.2, 0.4));
  look(0.0, 0.0);
}

TEST_F(HardwareCameraRobotTest, BadPanTiltValuesAre400AndMoveNothing) {
  look(0.3, 0.1);
  const auto status_of = [](const json& body) {
    return admin().put("/api/v1/camera/pan_tilt", body).status;
  };
  EXPECT_EQ(status_of(json{{"tilt", 0.0}}), 400);
  EXPECT_EQ(status_of(json{{"pan", "left"}, {"tilt", 0.0}}), 400);
  EXPECT_EQ(status_of(json{{"pan", 2.0}, {"tilt", 0.0}}), 400);   // beyond +/-90 deg
  EXPECT_EQ(status_of(json{{"pan", 0.0}, {"tilt", -0.6}}), 400);  // below -30 deg
  EXPECT_EQ(status_of(json{{"pan", 11.0}, {"tilt", 0.0}}), 400);
  const HttpReply out_of_range =
      admin().put("/api/v1/camera/pan_tilt", json{{"pan", -1.6}, {"tilt", 0.0}});
  ASSERT_EQ(out_of_range.status, 400);
  EXPECT_EQ(out_of_range.json().at("error").at("code"), "out_of_range");
  std::this_thread::sleep_for(300ms);
  EXPECT_TRUE(head_at(0.3, 0.1));
  look(0.0, 0.0);
}

TEST_F(HardwareCameraRobotTest, TheHeadRangeRangesTheTrackedTarget) {
  // Put the emulated robot 2 m from the office's west wall, facing it: the head's ranger looks
  // along the camera's axis at the wall.
  ASSERT_EQ(emulator_->command("set_pose 2.0 7.5 3.14159265"), "ok");
  look(0.0, 0.0);
  // The ranger takes a reading every 49 ms: the wall once it has looked from the new pose.
  ASSERT_TRUE(wait_until(
      [] {
        const std::optional<double> range_m = emulated_range_m();
        return range_m && *range_m < 2.5;
      },
      3s))
      << emulator_->command("maestro range");
  // Track the ball at the image centre: its range is the head's ranger's (the tracking stage
  // takes the head range of each tick, the ball being on the camera's axis).
  const HttpReply started = admin().post(
      "/api/v1/tracking", json{{"box", {{"x", 280}, {"y", 200}, {"w", 80}, {"h", 80}}}});
  ASSERT_EQ(started.status, 201) << started.body;
  // The first snapshot may carry the range of the tick before the wall came into view; each
  // ranged frame brings the newest. The LV-EZ's whole inches and the Maestro's 4.9 mV steps.
  json tracking;
  EXPECT_TRUE(wait_until(
      [&] {
        tracking = admin().get("/api/v1/tracking").json();
        const std::optional<double> wall_m = emulated_range_m();
        return tracking.contains("range_m") && tracking.at("range_m").is_number() && wall_m &&
               std::abs(tracking.at("range_m").get<double>() - *wall_m) < 0.04;
      },
      5s))
      << tracking.dump() << " " << emulator_->command("maestro range");
  EXPECT_EQ(tracking.value("status", ""), "tracking");
  EXPECT_EQ(admin().del("/api/v1/tracking").status, 200);
  ASSERT_EQ(emulator_->command("set_pose 2.0 7.5 0.0"), "ok");
  look(0.0, 0.0);
}

TEST_F(HardwareCameraRobotTest, ASilentMaestroIsReportedAndComesBackByItself) {
  for (const std::string fault : {"drop", "garbage", "unplug"}) {
    SCOPED_TRACE(fault);
    ASSERT_TRUE(wait_until([] { return device_ok("pan_tilt"); }, 10s));
    ASSERT_EQ(emulator_->command("fault pan_tilt " + fault), "ok");
    EXPECT_TRUE(wait_until([] { return device_down("pan_tilt"); }, 3s));
    // The other devices are not affected.
    EXPECT_TRUE(device_ok("base"));
    ASSERT_EQ(emulator_->command("clear pan_tilt"), "ok");
    EXPECT_TRUE(wait_until([] { return device_ok("pan_tilt"); }, 8s));
    // And the head follows commands again.
    look(0.2, 0.0);
    look(0.0, 0.0);
  }
  EXPECT_NE(admin().get("/metrics").body.find("mobot_device_reconnects_total{device=\"pan_tilt\"}"),
            std::string::npos);
}

// A fault of the head's devices stops the robot as a fault of any required sensor does: the
// camera robot's hardware config lists the head's ranger (`head_range`) in required_sensors.
TEST_F(HardwareCameraRobotTest, AMaestroFaultStopsTheRobot) {
  ASSERT_TRUE(robot_state(admin()).at("sensors").contains("head_range"))
      << robot_state(admin()).at("sensors").dump();
  ASSERT_EQ(emulator_->command("fault pan_tilt drop"), "ok");
  ASSERT_TRUE(wait_until([] { return !sensor("head_range").value("ok", true); }, 3s));
  EXPECT_FALSE(sensor("head_range").value("reason", "").empty());
  EXPECT_EQ(admin().post("/api/v1/teleop", json{{"v", 0.2}, {"w", 0.0}}).status, 200);
  ASSERT_TRUE(wait_robot_time(admin(), 0.5));
  EXPECT_EQ(robot_state(admin()).at("velocity").at("v").get<double>(), 0.0);
  ASSERT_EQ(emulator_->command("clear pan_tilt"), "ok");
  EXPECT_TRUE(wait_until([] { return sensor("head_range").value("ok", false); }, 8s));
}

}  // namespace
}  // namespace mobot::testing
