#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/control/command_mux.h"
#include "core/control/velocity_limits.h"
#include "drivers/backend_factory.h"

namespace mobot::server {

struct ServerSection {
  std::string bind_address = "127.0.0.1";
  std::uint16_t port = 8080;
  std::filesystem::path data_dir = "var";
  std::filesystem::path web_dir;  // empty: the dashboard built in the source tree
  // server.tls {cert, key} or --tls-cert/--tls-key, PEM files: both given, the port speaks only
  // https and wss; neither, only plain http and ws.
  std::filesystem::path tls_cert;  // the certificate chain, the server's own first
  std::filesystem::path tls_key;
  bool tls() const { return !tls_cert.empty(); }
};

struct RobotSection {
  std::string name = "r1";
  std::string profile = "r1";  // the robot the backend simulates or drives
  std::string kinematics = "differential";
  // Sensors whose silence stops the robot; the others only show as not ok.
  std::vector<std::string> required_sensors{"encoders", "laser"};
  double control_rate_hz = 50.0;
  // SCHED_FIFO priority of the control loop's thread (1..99), 0 for none: ticks start on time
  // however loaded the machine is, where the process may (root or CAP_SYS_NICE). Off by default:
  // on two cores it costs the stream fan-out's latency (BENCHMARKS.md).
  int realtime_priority = 0;
  double laser_rate_hz = 10.0;
  double sonar_rate_hz = 10.0;
  double compass_rate_hz = 10.0;
  double sensor_timeout_s = 0.5;  // a sensor silent this long stops the robot
  int teleop_ttl_ms = 300;
  control::VelocityLimits limits;
  std::vector<control::MuxSource> mux_sources{
      {"safety", 10, 0.2}, {"ir_safety", 9, 0.5}, {"teleop", 7, 1.0}, {"navigation", 5, 1.0}};
};

struct SimSection {
  std::string world = "office";
  std::filesystem::path worlds_dir;  // empty: the built-in worlds
  std::uint64_t seed = 1;
  double time_scale = 1.0;
  // The world's floor plan is stored and activated as the robot's map at start. false: the robot
  // starts without a map, as in a building nobody has mapped yet (docs/algorithms.md C7).
  bool provide_map = true;
  // sim.odometry: {scale_error, heading_drift_rad_per_m, step_noise_fraction}; each unset key
  // keeps the robot profile's value (docs/algorithms.md R2).
  drivers::SimOdometryErrors odometry;
  // R1's omni camera rendered as an image, its landmark bearings found in the pixels (E2,
  // measurement 3) instead of computed from the geometry.
  bool omni_pixels = false;
};

// Wheel geometry odometry integrates with. Unset (0) means the robot profile's nominal values;
// tests/bench/umbmark_runs.cpp (UMBmark, docs/algorithms.md E1) prints calibrated ones for here.
struct OdometrySection {
  double left_wheel_radius_m = 0.0;
  double right_wheel_radius_m = 0.0;
  double track_m = 0.0;
};

struct LocalizationSection {
  // The estimator the robot starts with, by its registered name; its options are in its own
  // section, estimators.NAME.
  std::string method = "ekf";
};

struct NavigationSection {
  double goal_tolerance_m = 0.05;
  double goal_tolerance_rad = 0.05;
  double max_linear_mps = 0.6;       // cruise cap while following a path (<= limits.max_linear_mps)
  double inscribed_radius_m = 0.42;  // R1: the 0.6 x 0.6 m footprint turning in place
  double avoidance_distance_m = 0.7;  // C4's d0
  // The tracker a goal without "controller" gets (a car-like robot cannot use lyapunov's turns on
  // the spot).
  std::string controller = "lyapunov";
  // The planner a goal without "planner" gets (a car-like robot needs hybrid_astar's curves).
  std::string planner = "astar";
};

// 3D sweeps with the tilting laser and their IPaBD obstacle maps (docs/algorithms.md R1, P1, P2).
struct SweepsSection {
  // The IPaBD results merge into the planning map as the 3D-obstacle layer; false plans on the 2D
  // map alone (the "2D trap" of P2: a beam under the robot's height is invisible to it).
  bool obstacle_layer = true;
  double floor_tolerance_m = 0.05;
  double max_range_m = 8.0;
  double pdbs_c0_m = 0.1;
  double pdbs_c1 = 0.05;
};

struct RecorderSection {
  double trajectory_rate_hz = 20.0;
  int flush_period_ms = 200;
};

struct StreamSection {
  int max_frames_per_topic = 4;
};

struct Config {
  std::string backend = "sim";
  std::string run_name;
  std::string extra_admin_token;  // --token: valid for this process only, never stored
  ServerSection server;
  RobotSection robot;
  SimSection sim;
  OdometrySection odometry;
  LocalizationSection localization;
  NavigationSection navigation;
  SweepsSection sweeps;
  RecorderSection recorder;
  StreamSection stream;
  // The whole config file, for the plugins to read their own sections from (null: defaults).
  YAML::Node document;
};

// A config file or flag that is wrong; the message names the key and what it accepts.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

Config load_config(const std::filesystem::path& file);
// Checks the cross-field rules (after flags are applied); throws ConfigError.
void validate_config(const Config& config);

}  // namespace mobot::server
