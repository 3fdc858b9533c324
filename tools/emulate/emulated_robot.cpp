#include "tools/emulate/emulated_robot.h"

#include <sstream>
#include <stdexcept>

#include "drivers/sim/robot_profile.h"
#include "tools/emulate/devices/dashgo_base_device.h"
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "tools/emulate/devices/maestro_device.h"
#include "tools/emulate/devices/modbus_sensor_bus_device.h"
#include "tools/emulate/devices/motion_mind_device.h"
#include "tools/emulate/devices/sharp_ir_device.h"
#include "tools/emulate/devices/sick_lms2xx_device.h"
#include "tools/emulate/devices/ydlidar_g4_device.h"

namespace mobot::emulate {
namespace {

constexpr const char* kRobotNames = "dashgo, r1, camera_robot";

std::vector<std::string> words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string word; in >> word;) out.push_back(word);
  return out;
}

// The Dashgo base's own commands: its e-stop button and the wheel set-points it last received.
std::string dashgo_base_command(DashgoBaseDevice& base, const std::vector<std::string>& args) {
  if (args.size() == 2 && args[0] == "estop" && (args[1] == "on" || args[1] == "off")) {
    base.set_estop_button(args[1] == "on");
    return "ok";
  }
  if (args.size() == 1 && args[0] == "wheels") {
    return "wheels " + std::to_string(base.target_left_tpf()) + " " +
           std::to_string(base.target_right_tpf());
  }
  return "error unknown command";
}

std::string optional_number(const std::optional<double>& value) {
  std::ostringstream out;
  if (value) {
    out << *value;
  } else {
    out << "none";
  }
  return out.str();
}

// The camera robot's Maestro: where its servos are, what its ranger sees, its error register.
std::string maestro_command(MaestroDevice& maestro, const std::vector<std::string>& args) {
  if (args.size() == 2 && args[1] == "head") {
    // Joint angles through the emulated servos' calibration, and their pulses in microseconds.
    std::ostringstream out;
    out << "head " << optional_number(maestro.pan_rad()) << ' '
        << optional_number(maestro.tilt_rad()) << ' '
        << maestro.position_qus(maestro.options().pan_channel) / 4.0 << ' '
        << maestro.position_qus(maestro.options().tilt_channel) / 4.0;
    return out.str();
  }
  if (args.size() == 2 && args[1] == "range") {
    return "range " + optional_number(maestro.ranger_range_m());
  }
  if (args.size() == 2 && args[1] == "errors") {
    return "errors " + std::to_string(maestro.errors());
  }
  if (args.size() == 3 && (args[1] == "raise" || args[1] == "keep")) {
    unsigned long bits = 0;
    try {
      bits = std::stoul(args[2]);
    } catch (const std::exception&) {
      return "error not a number: " + args[2];
    }
    if (bits > 0xFFFF) return "error the error register has 16 bits";
    if (args[1] == "raise") {
      maestro.raise_errors(static_cast<std::uint16_t>(bits));
    } else {
      maestro.keep_raising_errors(static_cast<std::uint16_t>(bits));
    }
    return "ok";
  }
  return "error unknown maestro command (head, range, errors, raise BITS, keep BITS)";
}

// A still scene for the camera robot's camera: a red ball in the middle of a grey room, which the
// tracker can lock on to (a box around the image centre).
void write_camera_frames(const std::filesystem::path& dir, const vision::PinholeCamera& camera) {
  std::filesystem::create_directories(dir);
  cv::Mat frame(camera.height_px, camera.width_px, CV_8UC3, cv::Scalar(128, 128, 128));
  cv::rectangle(frame, cv::Point(0, camera.height_px * 2 / 3),
                cv::Point(camera.width_px, camera.height_px), cv::Scalar(90, 100, 110), cv::FILLED);
  cv::circle(frame, cv::Point(camera.width_px / 2, camera.height_px / 2), camera.height_px / 10,
             cv::Scalar(30, 30, 220), cv::FILLED);
  for (int i = 0; i < 3; ++i) {
    const std::filesystem::path path = dir / ("frame_00" + std::to_string(i) + ".png");
    if (!cv::imwrite(path.string(), frame)) {
      throw std::runtime_error("cannot write the camera's frame " + path.string());
    }
  }
}

}  // namespace

EmulatedRobot::EmulatedRobot(EmulatedRobotOptions options)
    : options_(std::move(options)), world_(options_.world), seed_(options_.seed) {
  std::filesystem::create_directories(options_.link_dir);
  if (options_.robot == "dashgo") {
    make_dashgo();
  } else if (options_.robot == "r1") {
    make_r1();
  } else if (options_.robot == "camera_robot") {
    make_camera_robot();
  } else {
    throw std::invalid_argument("robot '" + options_.robot + "' is not one of " + kRobotNames);
  }
}

void EmulatedRobot::add_line(const std::string& role, std::unique_ptr<EmulatedDevice> device) {
  // Each device's link is named after its role in the hardware config (base, laser, ir).
  names_.push_back(role);
  lines_.push_back(
      std::make_unique<DeviceLine>(std::move(device), options_.link_dir / role, ++seed_));
}

DashgoBaseDevice& EmulatedRobot::make_dashgo_base_and_laser(const sim::RobotProfile& profile) {
  DashgoBaseDeviceOptions base;
  base.wheel_radius_m = profile.wheel_radius_m;
  base.track_m = profile.track_m;
  base.ticks_per_wheel_rev = static_cast<int>(profile.ticks_per_wheel_rev);
  base.sonars_in_base = profile.sonars_in_base;
  base.sonar_height_m = profile.sonar_height_m;
  base.sonar_range_max_m = profile.sonar_range_max_m;
  base.body_radius_m = profile.footprint_width_m / 2.0;
  base.seed = ++seed_;
  auto base_device = std::make_unique<DashgoBaseDevice>(base, world_);
  DashgoBaseDevice& base_model = *base_device;
  add_line("base", std::move(base_device));
  YdlidarG4Device::Options laser;
  laser.mounting_pose = profile.laser_in_base;
  laser.height_m = profile.laser_height_m;
  laser.min_range_m = profile.laser_range_min_m;
  laser.max_range_m = profile.laser_range_max_m;
  laser.seed = ++seed_;
  auto laser_device = std::make_unique<YdlidarG4Device>(world_, laser);
  YdlidarG4Device* laser_model = laser_device.get();
  add_line("laser", std::move(laser_device));
  if (!options_.trace_scans.empty()) trace_turns(*laser_model, *lines_.back());
  extra_command_ = [&base_model](const std::vector<std::string>& args) {
    return dashgo_base_command(base_model, args);
  };
  return base_model;
}

void EmulatedRobot::make_dashgo() {
  const sim::RobotProfile profile = sim::dashgo_d1_profile();
  make_dashgo_base_and_laser(profile);
  SharpIrDeviceOptions ir;
  ir.sensors_in_base = profile.ir_sensors_in_base;
  ir.height_m = profile.ir_height_m;
  ir.adc = profile.ir_adc;
  ir.seed = ++seed_;
  add_line("ir", std::make_unique<SharpIrDevice>(ir, world_));
}

void EmulatedRobot::make_r1() {
  const sim::RobotProfile profile = sim::r1_profile();
  // The wheels' boards (1, 2) and the tilt's (3) share one RS-232 line, the base's.
  MotionMindBusOptions boards;
  boards.seed = ++seed_;
  MotionMindBoardOptions left;
  left.address = 1;
  MotionMindBoardOptions right;
  right.address = 2;
  boards.boards = {left, right};
  MotionMindBoardOptions tilt;
  tilt.address = 3;
  tilt.counts_per_rev = 200.0 * 360.0;
  MotionMindTiltOptions tilt_axis;
  tilt_axis.counts_per_degree = 200.0;
  tilt.tilt = tilt_axis;
  boards.boards.push_back(tilt);
  auto bus = std::make_unique<MotionMindBus>(boards);
  coupling_ = std::make_unique<MotionMindBaseCoupling>(
      *bus, 1, 2, world_, MotionMindBaseGeometry{profile.track_m, profile.wheel_radius_m});
  add_line("base", std::move(bus));
  SickLms2xxDevice::Options laser;
  laser.mount_in_base = profile.laser_in_base;
  laser.mount_height_m = profile.laser_height_m;
  laser.seed = ++seed_;
  add_line("laser", std::make_unique<SickLms2xxDevice>(world_, laser));
  auto sensors = std::make_unique<ModbusSensorBusDevice>(world_, ModbusSensorBusOptions{}, ++seed_);
  ModbusSensorBusDevice* sensors_model = sensors.get();
  add_line("bus", std::move(sensors));
  extra_command_ = [sensors_model](const std::vector<std::string>& args) -> std::string {
    if (args.size() == 2 && args[0] == "limit" && (args[1] == "on" || args[1] == "off")) {
      sensors_model->set_limit_switch(args[1] == "on");
      return "ok";
    }
    if (args.size() == 3 && args[0] == "node" && (args[2] == "on" || args[2] == "off")) {
      try {
        sensors_model->set_node_present(std::stoi(args[1]), args[2] == "on");
      } catch (const std::exception& error) {
        return std::string("error ") + error.what();
      }
      return "ok";
    }
    return "error unknown command";
  };
}

void EmulatedRobot::make_camera_robot() {
  // R4 on the Dashgo's base: its Arduino (wheels, sonars) and lidar, the head's Maestro, and the
  // camera as a sequence of frames (OpenCV plays it as the hardware camera's source).
  const sim::RobotProfile profile = sim::camera_robot_profile();
  DashgoBaseDevice& base = make_dashgo_base_and_laser(profile);
  MaestroDeviceOptions maestro;
  maestro.head = profile.pan_tilt_camera->head;
  maestro.range_cone_rad = profile.pan_tilt_camera->range_cone_rad;
  auto maestro_device = std::make_unique<MaestroDevice>(maestro, world_);
  MaestroDevice& head = *maestro_device;
  add_line("pan_tilt", std::move(maestro_device));
  const std::filesystem::path frames = options_.link_dir / "frames";
  write_camera_frames(frames, profile.pan_tilt_camera->camera);
  settings_.push_back({"camera", "source", (frames / "frame_%03d.png").string()});
  extra_command_ = [&base, &head](const std::vector<std::string>& args) {
    if (!args.empty() && args[0] == "maestro") return maestro_command(head, args);
    return dashgo_base_command(base, args);
  };
}

void EmulatedRobot::trace_turns(YdlidarG4Device& laser, DeviceLine& line) {
  scan_trace_.open(options_.trace_scans, std::ios::app);
  if (!scan_trace_) {
    throw std::runtime_error("cannot open " + options_.trace_scans.string() + " for the trace");
  }
  laser.set_turn_end_hook([&line](std::uint64_t end_offset) { line.add_output_mark(end_offset); });
  // Flushed at once: a reader follows the file while the emulator runs.
  line.set_mark_listener([this](std::int64_t realtime_us) {
    scan_trace_ << realtime_us << '\n' << std::flush;
  });
}

EmulatedRobot::~EmulatedRobot() = default;

void EmulatedRobot::step(double now_s) {
  const std::lock_guard lock(mutex_);
  for (const auto& line : lines_) line->step(now_s);
  // R1's wheels are boards on a line: the base moves by what their shafts turned.
  if (coupling_) coupling_->update();
}

DeviceLine* EmulatedRobot::line_named(const std::string& name) {
  for (std::size_t i = 0; i < lines_.size(); ++i) {
    if (names_[i] == name) return lines_[i].get();
  }
  return nullptr;
}

std::string EmulatedRobot::command(const std::string& text, double now_s) {
  const std::lock_guard lock(mutex_);
  const std::vector<std::string> args = words(text);
  if (args.empty()) return "error empty command";
  if (args[0] == "fault" && (args.size() == 3 || args.size() == 4)) {
    DeviceLine* line = line_named(args[1]);
    const std::optional<LineFault> fault = line_fault_named(args[2]);
    if (!line) return "error no device " + args[1];
    if (!fault) return "error no fault " + args[2] + " (drop stall garbage checksum unplug)";
    const double duration_s = args.size() == 4 ? std::strtod(args[3].c_str(), nullptr) : 0.0;
    line->set_fault(*fault, now_s, duration_s);
    return "ok";
  }
  if (args[0] == "clear" && args.size() == 2) {
    DeviceLine* line = line_named(args[1]);
    if (!line) return "error no device " + args[1];
    line->clear_fault();
    return "ok";
  }
  if (args[0] == "pose" && args.size() == 1) {
    const geometry::Pose2D pose = world_.base_pose();
    std::ostringstream out;
    out << "pose " << pose.x << ' ' << pose.y << ' ' << pose.theta;
    return out.str();
  }
  if (args[0] == "ray" && args.size() == 5) {
    // What a range sensor at (x, y) looking along `angle` at `height` would see: tests compare
    // a driver's readings with it.
    const std::optional<double> range_m = world_.cast_ray(
        {std::strtod(args[1].c_str(), nullptr), std::strtod(args[2].c_str(), nullptr)},
        std::strtod(args[3].c_str(), nullptr), std::strtod(args[4].c_str(), nullptr), 100.0);
    return range_m ? "ray " + std::to_string(*range_m) : std::string("ray none");
  }
  if (args[0] == "set_pose" && args.size() == 4) {
    world_.set_base_pose({std::strtod(args[1].c_str(), nullptr),
                          std::strtod(args[2].c_str(), nullptr),
                          std::strtod(args[3].c_str(), nullptr)});
    return "ok";
  }
  return extra_command_ ? extra_command_(args) : "error unknown command";
}

std::vector<ConfigSetting> EmulatedRobot::config_settings() const {
  std::vector<ConfigSetting> out;
  for (const auto& [role, link] : links()) out.push_back({role, "device", link.string()});
  out.insert(out.end(), settings_.begin(), settings_.end());
  return out;
}

std::vector<std::pair<std::string, std::filesystem::path>> EmulatedRobot::links() const {
  std::vector<std::pair<std::string, std::filesystem::path>> out;
  for (std::size_t i = 0; i < lines_.size(); ++i) {
    out.emplace_back(names_[i], lines_[i]->port().link_path());
  }
  return out;
}

geometry::Pose2D EmulatedRobot::base_pose() const {
  const std::lock_guard lock(mutex_);
  return world_.base_pose();
}

}  // namespace mobot::emulate
