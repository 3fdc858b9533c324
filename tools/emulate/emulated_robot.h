#pragma once

#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "tools/emulate/device_line.h"
#include "tools/emulate/floor_plan_world.h"

namespace mobot::sim {
struct RobotProfile;
}  // namespace mobot::sim

namespace mobot::emulate {

class DashgoBaseDevice;
class MotionMindBaseCoupling;
class YdlidarG4Device;

struct EmulatedRobotOptions {
  std::string robot = "dashgo";    // dashgo | r1 | camera_robot
  std::filesystem::path link_dir;  // where the devices' links appear: DIR/base, DIR/laser, ...
  sim::World world;
  std::uint64_t seed = 1;
  // When set, one line is appended here per completed lidar turn: the CLOCK_REALTIME time in
  // microseconds at which the pty took the last byte of the packet that completes it (see
  // YdlidarG4Device::set_turn_end_hook), for measuring the host's latency from it.
  std::filesystem::path trace_scans;
};

// One value the emulator puts into the robot's hardware config: hardware.ROLE.KEY = value.
struct ConfigSetting {
  std::string role;
  std::string key;
  std::string value;
};

// The devices of one robot on their ptys, around one shared world: the emulated base moves the
// pose its lidar scans from. Driven by step() from one thread; command() may come from another.
class EmulatedRobot {
 public:
  explicit EmulatedRobot(EmulatedRobotOptions options);
  ~EmulatedRobot();

  // One pass over every line at `now_s` (seconds since start).
  void step(double now_s);
  // A line of the control protocol (see tools/emulate/main.cpp); returns the answer line.
  std::string command(const std::string& line, double now_s);

  // The devices' names and their links, in the order they were made.
  std::vector<std::pair<std::string, std::filesystem::path>> links() const;
  // What the hardware config needs for these devices: each line's `device`, and what a device
  // without a line needs (the camera robot's camera: `source`, the frames it plays).
  std::vector<ConfigSetting> config_settings() const;
  geometry::Pose2D base_pose() const;

 private:
  void add_line(const std::string& role, std::unique_ptr<EmulatedDevice> device);
  // The Dashgo's Arduino base (with its sonars) and its lidar, for the Dashgo and the camera
  // robot; returns the base's model.
  DashgoBaseDevice& make_dashgo_base_and_laser(const sim::RobotProfile& profile);
  void make_dashgo();
  void make_r1();
  void make_camera_robot();
  DeviceLine* line_named(const std::string& name);
  void trace_turns(YdlidarG4Device& laser, DeviceLine& line);

  EmulatedRobotOptions options_;
  FloorPlanWorld world_;
  mutable std::mutex mutex_;
  std::vector<std::unique_ptr<DeviceLine>> lines_;
  std::vector<std::string> names_;       // the role of each line
  std::uint64_t seed_ = 0;               // the last seed handed to a device
  std::vector<ConfigSetting> settings_;  // beyond the lines' devices
  // R1: moves the base by its wheel boards' turns (after lines_: it reads a model they own).
  std::unique_ptr<MotionMindBaseCoupling> coupling_;
  std::ofstream scan_trace_;
  // Robot-specific commands (the Dashgo's e-stop button).
  std::function<std::string(const std::vector<std::string>&)> extra_command_;
};

}  // namespace mobot::emulate
