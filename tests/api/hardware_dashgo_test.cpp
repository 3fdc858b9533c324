// mobotd --backend hardware driving the Dashgo D1's emulated devices (mobot-emulate dashgo) over
// pseudo-terminals: the real drivers, protocols and fault handling, without the robot.
#include <dirent.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

#include "support/api_test.h"
#include "support/goal_support.h"
#include "support/hardware_suite.h"

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

class HardwareDashgoTest : public HardwareSuite {
 protected:
  static void SetUpTestSuite() { start("dashgo", add_camera); }
  void SetUp() override {
    ASSERT_TRUE(server_->alive());
    // Each test starts with every device answering and the e-stop released.
    ASSERT_TRUE(wait_until([] { return all_sensors_ok(); }, 10s)) << robot_state(admin()).dump();
    admin().post("/api/v1/estop", json{{"engaged", false}});
  }

  // A camera that plays three PNG frames in a loop (OpenCV's image-sequence source), added to
  // the hardware config the emulator wrote.
  static void add_camera(const std::filesystem::path& config) {
    const std::filesystem::path frames = config.parent_path() / "frames";
    std::filesystem::create_directories(frames);
    for (int i = 0; i < 3; ++i) {
      std::vector<std::uint8_t> pixels(64 * 48, static_cast<std::uint8_t>(60 * i + 40));
      std::ofstream(frames / ("frame_00" + std::to_string(i) + ".png"), std::ios::binary)
          << make_png(64, 48, pixels);
    }
    std::ifstream in(config);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string section = "hardware:\n";
    const auto at = text.find(section);
    ASSERT_NE(at, std::string::npos) << text;
    text.insert(at + section.size(), "  camera: {driver: opencv, source: " +
                                         (frames / "frame_%03d.png").string() + ", rate_hz: 10}\n");
    std::ofstream(config) << text;
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

  static void check_faults(const std::string& device, const std::string& sensor_name);
  static std::size_t fault_events(const std::string& sensor_name) {
    std::size_t count = 0;
    for (const json& event : run_events(admin(), current_run_id(admin()))) {
      if (event.value("kind", "") == "fault" &&
          event.at("detail").value("sensor", "") == sensor_name) {
        ++count;
      }
    }
    return count;
  }
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
  // The emulated Arduino's battery: 12.4 V.
  EXPECT_NE(metrics.find("mobot_battery_volts{device=\"base\"} 12.4"), std::string::npos);
}

TEST_F(HardwareDashgoTest, TeleopTurnsTheWheelsAndTheOdometryFollows) {
  const EmulatedPose start = emulated_pose();
  const json pose_before = robot_state(admin()).at("pose");
  drive_for(admin(), 0.2, 0.0, 2.0);
  ASSERT_TRUE(wait_until([] { return wheel_setpoints().first == 0.0; }, 3s));
  // The wheels spin down after the zero set-point, and the odometry hears of it one encoder
  // reading later: both are compared once neither moves by a millimetre in 200 ms (on a loaded
  // machine the two reads are further apart than the last centimetres of the spin-down).
  EmulatedPose end = emulated_pose();
  json pose_after = robot_state(admin()).at("pose");
  std::this_thread::sleep_for(200ms);  // wait_until asks at once: the first comparison spans this
  ASSERT_TRUE(wait_until(
      [&] {
        const EmulatedPose now = emulated_pose();
        const json odometry_now = robot_state(admin()).at("pose");
        const bool still =
            std::hypot(now.x - end.x, now.y - end.y) < 1e-3 &&
            std::hypot(odometry_now.at("x").get<double>() - pose_after.at("x").get<double>(),
                       odometry_now.at("y").get<double>() - pose_after.at("y").get<double>()) <
                1e-3;
        end = now;
        pose_after = odometry_now;
        return still;
      },
      5s, 200ms));
  const double moved_m = std::hypot(end.x - start.x, end.y - start.y);
  EXPECT_GT(moved_m, 0.25);
  const double odometry_m =
      std::hypot(pose_after.at("x").get<double>() - pose_before.at("x").get<double>(),
                 pose_after.at("y").get<double>() - pose_before.at("y").get<double>());
  // The odometry counts what the wheels turned; the emulated wheels' PID holds 2 %.
  EXPECT_NEAR(odometry_m, moved_m, 0.1 * moved_m);
}

// Drives through each fault of `device` (its /robot sensor `sensor_name`): the robot stops at
// once, /robot and the events say why, and the device comes back by itself when the fault ends.
void HardwareDashgoTest::check_faults(const std::string& device, const std::string& sensor_name) {
  for (const std::string fault : {"unplug", "drop", "stall", "garbage", "checksum"}) {
    SCOPED_TRACE(device + " " + fault);
    ASSERT_TRUE(wait_until([] { return all_sensors_ok(); }, 10s));
    // Keep driving through the fault: the safety layer must win over the operator.
    std::atomic<bool> stop{false};
    std::thread driver([&] { drive_for(admin(), 0.1, 0.0, 30.0, [&] { return stop.load(); }); });
    ASSERT_TRUE(wait_until([] { return wheel_setpoints().first > 0.0; }, 3s));
    const std::size_t faults_before = fault_events(sensor_name);
    ASSERT_EQ(emulator_->command("fault " + device + " " + fault), "ok");
    ASSERT_TRUE(wait_until([&] { return !sensor(sensor_name).value("ok", true); }, 3s));
    const auto seen = std::chrono::steady_clock::now();
    EXPECT_TRUE(wait_until([] { return wheel_setpoints().first == 0.0; }, 1s));
    const double stop_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - seen).count();
    // The base's own cycle (20 ms) carries the zero set-point; the polls add their own.
    EXPECT_LT(stop_ms, 200.0);
    EXPECT_FALSE(sensor(sensor_name).value("reason", "").empty());
    // A new fault event of this sensor in the run (the recorder flushes every 200 ms).
    EXPECT_TRUE(wait_until([&] { return fault_events(sensor_name) > faults_before; }, 2s));
    stop = true;
    driver.join();
    ASSERT_EQ(emulator_->command("clear " + device), "ok");
    EXPECT_TRUE(wait_until([&] { return sensor(sensor_name).value("ok", false); }, 8s))
        << sensor(sensor_name).dump();
  }
}

TEST_F(HardwareDashgoTest, EachFaultOfTheIrBoardStopsTheRobotAndRecovers) {
  check_faults("ir", "ir");
}

TEST_F(HardwareDashgoTest, EachFaultOfTheLidarStopsTheRobotAndRecovers) {
  check_faults("laser", "laser");
}

TEST_F(HardwareDashgoTest, TheLidarStreamsWholeTurnsAtItsRateWithTheRightGeometry) {
  WsClient client(server_->port(), server_->token());
  client.send(json{{"op", "subscribe"}, {"topics", {"scan"}}, {"encoding", "json"}});
  ASSERT_TRUE(client.read_until("subscribed", 5s));
  const EmulatedPose pose = emulated_pose();  // the robot stands still
  std::vector<json> scans;
  const auto start = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - start < 3s) {
    const auto frame = client.read(1s);
    if (frame && frame->text() && frame->json().value("topic", "") == "scan") {
      scans.push_back(frame->json().at("data"));
    }
  }
  // The emulated G4 turns at 7 Hz.
  EXPECT_GE(scans.size(), 18U);
  EXPECT_LE(scans.size(), 24U);
  ASSERT_FALSE(scans.empty());
  const json& scan = scans.back();
  const auto& ranges = scan.at("ranges");
  ASSERT_EQ(ranges.size(), 720U);
  EXPECT_NEAR(scan.at("angle_min").get<double>(), -M_PI, 1e-5);
  EXPECT_NEAR(scan.at("angle_increment").get<double>(), 2.0 * M_PI / 720.0, 1e-6);
  // Every tenth bin against the floor plan seen from the lidar (on the base's centre, 0.2 m up).
  // A bin holds the nearest sample that fell in it, so its range lies between the nearest and
  // the farthest surface across the bin's half degree, give or take the G4's noise.
  auto ray = [&](double bearing) {
    std::istringstream in(emulator_->command("ray " + std::to_string(pose.x) + " " +
                                             std::to_string(pose.y) + " " +
                                             std::to_string(pose.theta + bearing) + " 0.2"));
    std::string word;
    double range_m = std::numeric_limits<double>::infinity();
    in >> word >> range_m;
    return range_m > 16.0 ? std::numeric_limits<double>::infinity() : range_m;
  };
  const double increment = 2.0 * M_PI / 720.0;
  int checked = 0;
  int outside = 0;
  for (int bin = 0; bin < 720; bin += 10) {
    double nearest_m = std::numeric_limits<double>::infinity();
    double farthest_m = 0.0;
    // Bin i is centred on -pi + i * increment; a little wider than the bin for the angle's
    // quantisation (1/64 degree) and the distance-dependent angle correction.
    for (int k = -3; k <= 3; ++k) {
      const double range_m = ray(-M_PI + (bin + k / 5.0) * increment);
      nearest_m = std::min(nearest_m, range_m);
      farthest_m = std::max(farthest_m, range_m);
    }
    if (!ranges[bin].is_number()) continue;  // +infinity: nothing within the G4's 16 m
    const double range_m = ranges[bin].get<double>();
    if (range_m < 0.1) continue;  // no sample fell in the bin
    ++checked;
    const double tolerance_m = 0.03 + 0.015 * range_m;
    if (range_m < nearest_m - tolerance_m || range_m > farthest_m + tolerance_m) {
      ++outside;
      ADD_FAILURE() << "bin " << bin << ": " << range_m << " m, the plan says " << nearest_m << ".."
                    << farthest_m << " m; neighbours " << ranges[bin - 2] << " " << ranges[bin - 1]
                    << " " << ranges[bin + 1] << " " << ranges[bin + 2]
                    << "; plan at -1, +1 bin: " << ray(-M_PI + (bin - 1) * increment) << " "
                    << ray(-M_PI + (bin + 1) * increment);
    }
  }
  EXPECT_GE(checked, 50);
  EXPECT_EQ(outside, 0);
}

TEST_F(HardwareDashgoTest, TheCameraStreamsJpegFramesAtItsRate) {
  WsClient client(server_->port(), server_->token());
  client.send(json{{"op", "subscribe"}, {"topics", {"camera"}}, {"encoding", "binary"}});
  ASSERT_TRUE(client.read_until("subscribed", 5s));
  int frames = 0;
  const auto start = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - start < 2s) {
    const auto frame = client.read_binary(1s);
    if (!frame) continue;
    const std::string& bytes = frame->payload;
    ASSERT_GE(bytes.size(), 36U);
    ASSERT_EQ(bytes.substr(0, 4), "MBT1");
    std::uint16_t topic = 0;
    std::uint16_t header_bytes = 0;
    std::memcpy(&topic, bytes.data() + 4, 2);
    std::memcpy(&header_bytes, bytes.data() + 6, 2);
    EXPECT_EQ(topic, 5);
    // The body is a JPEG file: it starts with the SOI marker.
    EXPECT_EQ(static_cast<unsigned char>(bytes[header_bytes]), 0xFF);
    EXPECT_EQ(static_cast<unsigned char>(bytes[header_bytes + 1]), 0xD8);
    ++frames;
  }
  // 10 Hz for 2 s.
  EXPECT_GE(frames, 15);
  EXPECT_LE(frames, 22);
}

TEST_F(HardwareDashgoTest, AGoalSucceedsOnTheEmulatedFloorPlan) {
  // The office's floor plan as the robot's map, and the robot told where it stands.
  std::ifstream image(std::string(MOBOT_SOURCE_ROOT) + "/drivers/sim/worlds/office/office.pgm",
                      std::ios::binary);
  const std::string pgm((std::istreambuf_iterator<char>(image)), std::istreambuf_iterator<char>());
  ASSERT_FALSE(pgm.empty());
  json body = map_import_body("office", pgm, 0.05);
  body["origin"] = json{{"x", 0.0}, {"y", 0.0}, {"theta", 0.0}};  // the world's own
  const HttpReply imported = admin().post("/api/v1/maps", body);
  ASSERT_EQ(imported.status, 201) << imported.body;
  const auto map_id = imported.json().at("id").get<std::int64_t>();
  ASSERT_EQ(admin().post("/api/v1/maps/" + std::to_string(map_id) + "/activate", "").status, 200);
  const EmulatedPose start = emulated_pose();
  ASSERT_EQ(admin()
                .post("/api/v1/localization/pose",
                      json{{"x", start.x}, {"y", start.y}, {"theta", start.theta}})
                .status,
            200);
  // 1.5 m ahead along the corridor the office starts in.
  const double goal_x = start.x + 1.5 * std::cos(start.theta);
  const double goal_y = start.y + 1.5 * std::sin(start.theta);
  const HttpReply goal = post_goal(admin(), goal_x, goal_y, start.theta);
  ASSERT_EQ(goal.status, 201) << goal.body;
  const json result = wait_goal_end(admin(), goal.json().at("id").get<std::int64_t>(), 40.0);
  EXPECT_EQ(result.value("status", ""), "succeeded") << result.dump();
  const EmulatedPose end = emulated_pose();
  EXPECT_LT(std::hypot(end.x - goal_x, end.y - goal_y), 0.25) << end.x << " " << end.y;
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
