// mobot-emulate: a robot's devices on pseudo-terminals, speaking their real protocols from the
// device's side, so mobotd --backend hardware runs without the robot.
//
//   mobot-emulate dashgo|r1|camera_robot --dir /tmp/dashgo [--world office] [--seed 1]
//                 [--trace-scans FILE]
//
// camera_robot (docs/algorithms.md R4 on hardware): the Dashgo's base and lidar, the camera
// head's Pololu Maestro (two servos, the ultrasonic ranger), and the camera as frames of a still
// scene written to DIR/frames (a red ball at the image centre), which the config's camera plays.
//
// --trace-scans appends to FILE, per completed lidar turn, the CLOCK_REALTIME time in microseconds
// at which the last byte of the packet completing it went to the pty (tests/bench/scan_latency.py
// measures the scan latency of mobotd from it).
//
// Prints one line per device ("base /tmp/dashgo/base -> /dev/pts/5"), the config it wrote
// ("config /tmp/dashgo/mobotd.yaml": the robot's hardware config with these devices), then
// "ready". Then it reads commands on stdin, one per line, and answers each with one line:
//   fault DEVICE drop|stall|garbage|checksum|unplug [SECONDS]   (without SECONDS: until clear)
//   clear DEVICE
//   estop on|off               the base's emergency button (dashgo)
//   limit on|off               the limit switch on the RS-485 bus (r1)
//   node N on|off              a node of the RS-485 bus answers or not (r1)
//   wheels                     -> "wheels L R", the base's wheel set-points (dashgo, camera_robot:
//                                 ticks/frame)
//   maestro head               -> "head PAN TILT PAN_US TILT_US": the head's servos (rad, "none"
//                                 while off, and their pulses) (camera_robot)
//   maestro range              -> "range METRES" or "range none": what the head's ranger sees
//   maestro errors             -> "errors BITS": the Maestro's error register (not cleared)
//   maestro raise|keep BITS    the Maestro detects these errors once, or every 10 ms (keep 0 ends)
//   pose                       -> "pose X Y THETA", the emulated base's true pose
//   set_pose X Y THETA
//   ray X Y ANGLE HEIGHT       -> "ray RANGE" (or "ray none"): the floor plan seen from (X, Y)
//   quit                       (end of input keeps the devices running until SIGINT/SIGTERM)
#include <yaml-cpp/yaml.h>
#include <CLI/CLI.hpp>

#include <atomic>
#include <chrono>
#include <csignal>
#include <fstream>
#include <iostream>
#include <thread>

#include "drivers/sim/world.h"
#include "tools/emulate/emulated_robot.h"

namespace {

std::atomic<bool> g_stop{false};

void on_signal(int) { g_stop = true; }

// The robot's hardware config with the emulated devices' links as its device paths (and what
// else the emulated devices need there).
void write_config(const std::filesystem::path& template_path, const std::filesystem::path& out,
                  const mobot::emulate::EmulatedRobot& robot) {
  YAML::Node config = YAML::LoadFile(template_path.string());
  for (const auto& [role, key, value] : robot.config_settings()) {
    if (config["hardware"][role]) config["hardware"][role][key] = value;
  }
  std::ofstream file(out);
  file << "# Written by mobot-emulate from " << template_path.string() << "\n" << config << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"mobot-emulate: a robot's devices on pseudo-terminals"};
  std::string robot_name = "dashgo";
  std::filesystem::path dir;
  std::string world_name = "office";
  std::uint64_t seed = 1;
  std::filesystem::path config_template;
  std::filesystem::path trace_scans;
  const std::vector<std::string> robots{"dashgo", "r1", "camera_robot"};
  cli.add_option("robot", robot_name, "dashgo | r1 | camera_robot")->check(CLI::IsMember(robots));
  cli.add_option("--dir", dir, "where the device links and the config go")->required();
  cli.add_option("--world", world_name, "a built-in world or a world.yaml");
  cli.add_option("--seed", seed, "noise seed");
  cli.add_option("--config-template", config_template,
                 "the hardware config to fill in (default: deploy/config/ of this source tree)");
  cli.add_option("--trace-scans", trace_scans,
                 "append the realtime us at which each lidar turn's last packet was written");
  CLI11_PARSE(cli, argc, argv);
  if (config_template.empty()) {
    // Each robot's hardware profile: deploy/config/<file>_hardware.yaml.
    const std::string file = robot_name == "dashgo" ? "dashgo_d1" : robot_name;
    config_template =
        std::filesystem::path(MOBOT_SOURCE_ROOT) / "deploy/config" / (file + "_hardware.yaml");
  }

  try {
    mobot::emulate::EmulatedRobotOptions options;
    options.robot = robot_name;
    options.link_dir = dir;
    options.world =
        mobot::sim::load_world(mobot::sim::resolve_world(MOBOT_DEFAULT_WORLDS_DIR, world_name));
    options.seed = seed;
    options.trace_scans = trace_scans;
    mobot::emulate::EmulatedRobot robot(std::move(options));
    const std::filesystem::path config_path = dir / "mobotd.yaml";
    write_config(config_template, config_path, robot);

    for (const auto& [name, link] : robot.links()) {
      std::cout << name << ' ' << link.string() << " -> "
                << std::filesystem::read_symlink(link).string() << '\n';
    }
    std::cout << "config " << config_path.string() << "\nready" << std::endl;

    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    const auto start = std::chrono::steady_clock::now();
    auto seconds = [start] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    // The devices live on their own thread, at a 1 ms grain: a 230400 baud line carries 23
    // bytes in that time.
    std::jthread devices([&](const std::stop_token& stop) {
      while (!stop.stop_requested() && !g_stop) {
        robot.step(seconds());
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    });
    bool quit = false;
    for (std::string line; !g_stop && std::getline(std::cin, line);) {
      if (line == "quit") {
        quit = true;
        break;
      }
      if (line.empty()) continue;
      std::cout << robot.command(line, seconds()) << std::endl;
    }
    // Started in the background (no input), the devices live on until a signal stops them.
    while (!quit && !g_stop) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    g_stop = true;
  } catch (const std::exception& error) {
    std::cerr << "mobot-emulate: " << error.what() << '\n';
    return 1;
  }
  return 0;
}
