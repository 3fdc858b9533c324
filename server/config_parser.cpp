#include "server/config_parser.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <sstream>

namespace mobot::server {
namespace {

template <class T>
void check_range(const std::string& key, T value, T min, T max) {
  if (!(value >= min && value <= max)) {
    std::ostringstream message;
    message << key << ": " << value << " is outside the allowed range [" << min << ", " << max
            << "]";
    throw ConfigError(message.str());
  }
}

// A mapping's key as a name: "{[a]: 1}" is valid YAML whose key is a list, which no config has.
std::string key_name(const YAML::Node& key, const std::string& where) {
  if (!key.IsScalar()) throw ConfigError(where + ": keys are plain names, not lists or mappings");
  return key.Scalar();
}

// Reads file keys as "section.key" so every message names the full path of the bad key.
class Reader {
 public:
  explicit Reader(const YAML::Node& root) : root_(root) {}

  template <class T>
  void read(const char* section, const char* key, T& out) const {
    const YAML::Node node = lookup(section, key);
    if (!node) return;
    try {
      out = node.as<T>();
    } catch (const YAML::Exception&) {
      throw ConfigError(path(section, key) + ": expected " + type_name<T>());
    }
  }

  void read_number(const char* section, const char* key, double& out, double min,
                   double max) const {
    read(section, key, out);
    check_range(path(section, key), out, min, max);
  }

  void read_int(const char* section, const char* key, int& out, int min, int max) const {
    read(section, key, out);
    check_range(path(section, key), out, min, max);
  }

  YAML::Node lookup(const char* section, const char* key) const {
    if (section == nullptr) return root_[key];
    const YAML::Node parent = root_[section];
    if (!parent) return YAML::Node(YAML::NodeType::Undefined);
    if (!parent.IsMap()) throw ConfigError(std::string(section) + ": expected a mapping");
    return parent[key];
  }

  static std::string path(const char* section, const char* key) {
    return section == nullptr ? key : std::string(section) + "." + key;
  }

 private:
  template <class T>
  static std::string type_name() {
    if constexpr (std::is_same_v<T, std::string>) return "a string";
    if constexpr (std::is_same_v<T, bool>) return "true or false";
    if constexpr (std::is_floating_point_v<T>) return "a number";
    return "an integer";
  }

  YAML::Node root_;
};

void read_localization(const Reader& reader, LocalizationSection& localization) {
  reader.read("localization", "method", localization.method);
}

void read_mux(const Reader& reader, RobotSection& robot) {
  const YAML::Node sources = reader.lookup(nullptr, "mux");
  if (!sources) return;
  if (!sources.IsSequence() || sources.size() == 0) {
    throw ConfigError("mux: expected a list of {name, priority, timeout_s}");
  }
  robot.mux_sources.clear();
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const std::string where = "mux[" + std::to_string(i) + "]";
    try {
      control::MuxSource source{sources[i]["name"].as<std::string>(),
                                sources[i]["priority"].as<int>(),
                                sources[i]["timeout_s"].as<double>()};
      check_range(where + ".timeout_s", source.timeout_s, 0.01, 60.0);
      robot.mux_sources.push_back(std::move(source));
    } catch (const YAML::Exception&) {
      throw ConfigError(where + ": expected {name: string, priority: int, timeout_s: number}");
    }
  }
}

// The simulator's odometry errors, a mapping inside sim: each key optional, every key known.
void read_sim_odometry(const Reader& reader, SimSection& sim) {
  const YAML::Node node = reader.lookup("sim", "odometry");
  if (!node || node.IsNull()) return;
  if (!node.IsMap()) throw ConfigError("sim.odometry: expected a mapping");
  static const std::set<std::string> kKeys{"scale_error", "heading_drift_rad_per_m",
                                           "step_noise_fraction"};
  for (const auto& field : node) {
    const auto name = key_name(field.first, "sim.odometry");
    if (!kKeys.contains(name)) throw ConfigError("sim.odometry." + name + ": unknown key");
  }
  const auto number = [&node](const std::string& key, double min,
                              double max) -> std::optional<double> {
    const YAML::Node value = node[key];
    if (!value) return std::nullopt;
    double out = 0.0;
    try {
      out = value.as<double>();
    } catch (const YAML::Exception&) {
      throw ConfigError("sim.odometry." + key + ": expected a number");
    }
    check_range("sim.odometry." + key, out, min, max);
    return out;
  };
  sim.odometry.scale_error = number("scale_error", -0.2, 0.2);
  sim.odometry.heading_drift_rad_per_m = number("heading_drift_rad_per_m", -0.1, 0.1);
  sim.odometry.step_noise_fraction = number("step_noise_fraction", 0.0, 0.3);
}

// server.tls: {cert: PATH, key: PATH}, both file paths; that both are there is a rule across keys
// (check_config_rules), since the flags may give either.
void read_server_tls(const Reader& reader, ServerSection& server) {
  const YAML::Node node = reader.lookup("server", "tls");
  if (!node || node.IsNull()) return;
  if (!node.IsMap()) throw ConfigError("server.tls: expected a mapping {cert: PATH, key: PATH}");
  for (const auto& field : node) {
    const auto name = key_name(field.first, "server.tls");
    if (name != "cert" && name != "key") throw ConfigError("server.tls." + name + ": unknown key");
  }
  const auto path = [&node](const std::string& key) -> std::filesystem::path {
    const YAML::Node value = node[key];
    if (!value) return {};
    if (!value.IsScalar() || value.Scalar().empty()) {
      throw ConfigError("server.tls." + key + ": expected a file path");
    }
    return value.Scalar();
  };
  server.tls_cert = path("cert");
  server.tls_key = path("key");
}

// The sensors whose silence or fault stops the robot: a list of known sensor names.
void read_required_sensors(const Reader& reader, RobotSection& robot) {
  const YAML::Node node = reader.lookup("robot", "required_sensors");
  if (!node) return;
  static const std::set<std::string> kNames{"encoders", "laser",   "sonar",
                                            "ir",       "compass", "head_range"};
  std::vector<std::string> names;
  try {
    names = node.as<std::vector<std::string>>();
  } catch (const YAML::Exception&) {
    throw ConfigError("robot.required_sensors: expected a list of sensor names");
  }
  for (const std::string& name : names) {
    if (!kNames.contains(name)) {
      throw ConfigError("robot.required_sensors: '" + name +
                        "' is not one of encoders, laser, sonar, ir, compass, head_range");
    }
  }
  robot.required_sensors = names;
}

// A misspelt key would otherwise be ignored silently and the default used instead.
void reject_unknown_keys(const YAML::Node& root) {
  static const std::map<std::string, std::set<std::string>> kKnown{
      {"server", {"bind", "port", "data_dir", "web_dir", "tls"}},
      {"robot",
       {"name", "profile", "kinematics", "control_rate_hz", "realtime_priority", "laser_rate_hz",
        "sonar_rate_hz", "compass_rate_hz", "sensor_timeout_s", "teleop_ttl_ms",
        "required_sensors"}},
      {"limits",
       {"max_linear_mps", "max_angular_radps", "max_linear_accel_mps2",
        "max_angular_accel_radps2"}},
      {"sim", {"world", "worlds_dir", "seed", "time_scale", "odometry", "provide_map", "omni_pixels"}},
      {"odometry", {"left_wheel_radius_m", "right_wheel_radius_m", "track_m"}},
      {"localization", {"method"}},
      {"navigation",
       {"goal_tolerance_m", "goal_tolerance_rad", "max_linear_mps", "inscribed_radius_m",
        "avoidance_distance_m", "controller", "planner"}},
      {"sweeps", {"obstacle_layer", "floor_tolerance_m", "max_range_m", "pdbs_c0_m", "pdbs_c1"}},
      {"recorder", {"trajectory_rate_hz", "flush_period_ms"}},
      {"stream", {"max_frames_per_topic"}},
  };
  // Plugin sections: each plugin checks its own keys (server/plugins).
  static const std::set<std::string> kScalars{
      "backend",    "run_name", "mux",      "planners",  "controllers",     "estimators",
      "kinematics", "slam",     "costmaps", "ir_safety", "sonar_emergency", "hardware"};
  for (const auto& entry : root) {
    const auto key = key_name(entry.first, "the top level");
    if (kScalars.contains(key)) continue;
    const auto section = kKnown.find(key);
    if (section == kKnown.end()) throw ConfigError(key + ": unknown key");
    if (!entry.second.IsMap()) continue;  // the reader reports the type
    for (const auto& field : entry.second) {
      const auto name = key_name(field.first, key);
      if (!section->second.contains(name)) throw ConfigError(key + "." + name + ": unknown key");
    }
  }
}

Config read_config(std::string_view yaml_text, const std::string& source) {
  const YAML::Node root = YAML::Load(std::string(yaml_text));
  if (root.IsNull()) return {};
  if (!root.IsMap()) throw ConfigError(source + ": expected a mapping at the top level");

  reject_unknown_keys(root);
  Config config;
  config.document = root;
  const Reader reader(root);
  reader.read(nullptr, "backend", config.backend);
  reader.read(nullptr, "run_name", config.run_name);

  reader.read("server", "bind", config.server.bind_address);
  int port = config.server.port;
  reader.read_int("server", "port", port, 0, 65535);
  config.server.port = static_cast<std::uint16_t>(port);
  std::string path;
  reader.read("server", "data_dir", path);
  if (!path.empty()) config.server.data_dir = path;
  path.clear();
  reader.read("server", "web_dir", path);
  if (!path.empty()) config.server.web_dir = path;
  read_server_tls(reader, config.server);

  RobotSection& robot = config.robot;
  reader.read("robot", "name", robot.name);
  reader.read("robot", "profile", robot.profile);
  reader.read("robot", "kinematics", robot.kinematics);
  reader.read_number("robot", "control_rate_hz", robot.control_rate_hz, 5.0, 200.0);
  reader.read_int("robot", "realtime_priority", robot.realtime_priority, 0, 99);
  reader.read_number("robot", "laser_rate_hz", robot.laser_rate_hz, 1.0, 40.0);
  reader.read_number("robot", "sonar_rate_hz", robot.sonar_rate_hz, 1.0, 50.0);
  reader.read_number("robot", "compass_rate_hz", robot.compass_rate_hz, 1.0, 50.0);
  reader.read_number("robot", "sensor_timeout_s", robot.sensor_timeout_s, 0.05, 10.0);
  reader.read_int("robot", "teleop_ttl_ms", robot.teleop_ttl_ms, 50, 1000);
  read_required_sensors(reader, robot);
  reader.read_number("limits", "max_linear_mps", robot.limits.max_linear_mps, 0.01, 10.0);
  reader.read_number("limits", "max_angular_radps", robot.limits.max_angular_radps, 0.01, 10.0);
  reader.read_number("limits", "max_linear_accel_mps2", robot.limits.max_linear_accel_mps2, 0.01,
                     20.0);
  reader.read_number("limits", "max_angular_accel_radps2", robot.limits.max_angular_accel_radps2,
                     0.01, 50.0);
  read_mux(reader, robot);

  reader.read("sim", "world", config.sim.world);
  path.clear();
  reader.read("sim", "worlds_dir", path);
  if (!path.empty()) config.sim.worlds_dir = path;
  reader.read("sim", "seed", config.sim.seed);
  reader.read_number("sim", "time_scale", config.sim.time_scale, 0.1, 100.0);
  reader.read("sim", "provide_map", config.sim.provide_map);
  reader.read("sim", "omni_pixels", config.sim.omni_pixels);
  read_sim_odometry(reader, config.sim);

  reader.read_number("odometry", "left_wheel_radius_m", config.odometry.left_wheel_radius_m, 0.0,
                     1.0);
  reader.read_number("odometry", "right_wheel_radius_m", config.odometry.right_wheel_radius_m, 0.0,
                     1.0);
  reader.read_number("odometry", "track_m", config.odometry.track_m, 0.0, 5.0);
  read_localization(reader, config.localization);
  NavigationSection& navigation = config.navigation;
  reader.read_number("navigation", "goal_tolerance_m", navigation.goal_tolerance_m, 0.01, 1.0);
  reader.read_number("navigation", "goal_tolerance_rad", navigation.goal_tolerance_rad, 0.01, 1.0);
  reader.read_number("navigation", "max_linear_mps", navigation.max_linear_mps, 0.05, 10.0);
  reader.read_number("navigation", "inscribed_radius_m", navigation.inscribed_radius_m, 0.05, 2.0);
  reader.read_number("navigation", "avoidance_distance_m", navigation.avoidance_distance_m, 0.1,
                     4.0);
  reader.read("navigation", "controller", navigation.controller);
  reader.read("navigation", "planner", navigation.planner);

  SweepsSection& sweeps = config.sweeps;
  reader.read("sweeps", "obstacle_layer", sweeps.obstacle_layer);
  reader.read_number("sweeps", "floor_tolerance_m", sweeps.floor_tolerance_m, 0.0, 0.5);
  reader.read_number("sweeps", "max_range_m", sweeps.max_range_m, 1.0, 40.0);
  reader.read_number("sweeps", "pdbs_c0_m", sweeps.pdbs_c0_m, 0.0, 2.0);
  reader.read_number("sweeps", "pdbs_c1", sweeps.pdbs_c1, 0.0, 1.0);

  reader.read_number("recorder", "trajectory_rate_hz", config.recorder.trajectory_rate_hz, 10.0,
                     100.0);
  reader.read_int("recorder", "flush_period_ms", config.recorder.flush_period_ms, 10, 5000);
  reader.read_int("stream", "max_frames_per_topic", config.stream.max_frames_per_topic, 1, 64);
  return config;
}

}  // namespace

Config parse_config(std::string_view yaml_text, const std::string& source) {
  try {
    return read_config(yaml_text, source);
  } catch (const YAML::Exception& error) {
    // The YAML itself is broken, or a node has a shape no reader expected; the message has its
    // line and column.
    throw ConfigError(source + ": " + error.what());
  }
}

void check_config_rules(const Config& config) {
  if (config.server.tls_cert.empty() != config.server.tls_key.empty()) {
    throw ConfigError(config.server.tls_cert.empty()
                          ? "server.tls.cert: missing: TLS needs the certificate chain "
                            "(server.tls.cert or --tls-cert) besides the key"
                          : "server.tls.key: missing: TLS needs the private key "
                            "(server.tls.key or --tls-key) besides the certificate");
  }
  if (config.backend != "sim" && config.backend != "hardware") {
    throw ConfigError("backend: '" + config.backend + "' is not one of sim, hardware");
  }
  check_range("sim.time_scale", config.sim.time_scale, 0.1, 100.0);
  if (config.backend == "hardware" && config.sim.time_scale != 1.0) {
    throw ConfigError("sim.time_scale: the hardware backend runs in real time (1), not " +
                      std::to_string(config.sim.time_scale));
  }
  check_range("robot.laser_rate_hz", config.robot.laser_rate_hz, 1.0, config.robot.control_rate_hz);
  check_range("navigation.max_linear_mps", config.navigation.max_linear_mps, 0.05,
              config.robot.limits.max_linear_mps);
  bool has_teleop = false;
  bool has_safety = false;
  for (const auto& source : config.robot.mux_sources) {
    has_teleop = has_teleop || source.name == "teleop";
    has_safety = has_safety || source.name == "safety";
  }
  if (!has_teleop || !has_safety) {
    throw ConfigError("mux: the sources 'safety' and 'teleop' are required");
  }
}

}  // namespace mobot::server
