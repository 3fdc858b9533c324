// mobot-slam: runs core/slam's GraphSlam over a CARMEN log (docs/algorithms.md E5) and writes the
// optimised trajectory, the map (map_server PGM + YAML) and, given a reference, the ATE.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/mapping/map_image_codec.h"
#include "core/slam/carmen_log.h"
#include "core/slam/graph_slam.h"
#include "core/slam/trajectory_error.h"
#include "tools/slam/text_input.h"

namespace {

using mobot::geometry::Point2D;
using mobot::geometry::Pose2D;

struct Reference {
  std::vector<double> t;
  std::vector<Point2D> positions;
};

// `t x y theta` lines; blank lines and # comments skipped.
Reference read_reference(const std::string& path) {
  Reference ref;
  const std::vector<std::string> lines = mobot::tools::read_text_lines(path);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].empty() || lines[i][0] == '#') continue;
    std::istringstream in(lines[i]);
    double t = 0.0, x = 0.0, y = 0.0, theta = 0.0;
    if (!(in >> t >> x >> y >> theta)) {
      std::cerr << path << ":" << i + 1 << ": not 't x y theta', skipped\n";
      continue;
    }
    ref.t.push_back(t);
    ref.positions.push_back({x, y});
  }
  return ref;
}

// `name=value` overrides of GraphSlamOptions, for experiments; the defaults are what is measured.
bool set_option(mobot::slam::GraphSlamOptions& o, const std::string& assignment) {
  const std::size_t eq = assignment.find('=');
  if (eq == std::string::npos) return false;
  const std::string name = assignment.substr(0, eq);
  double value = 0.0;
  try {
    value = std::stod(assignment.substr(eq + 1));
  } catch (const std::exception&) {
    return false;
  }
  struct Field {
    const char* name;
    double* real;
    int* integer;
  };
  const Field fields[] = {
      {"max_range_m", &o.max_range_m, nullptr},
      {"voxel_size_m", &o.voxel_size_m, nullptr},
      {"min_travel_m", &o.min_travel_m, nullptr},
      {"min_rotation_rad", &o.min_rotation_rad, nullptr},
      {"resolution_m", &o.resolution_m, nullptr},
      {"match_field_sigma_m", &o.match_field_sigma_m, nullptr},
      {"local_map_nodes", nullptr, &o.local_map_nodes},
      {"local_map_chain_distance_m", &o.local_map_chain_distance_m, nullptr},
      {"local_search_linear_m", &o.local_search_linear_m, nullptr},
      {"local_search_angular_rad", &o.local_search_angular_rad, nullptr},
      {"angular_step_rad", &o.angular_step_rad, nullptr},
      {"local_min_score", &o.local_min_score, nullptr},
      {"refine_max_iterations", nullptr, &o.refine_max_iterations},
      {"refine_translation_weight", &o.refine_translation_weight, nullptr},
      {"refine_rotation_weight", &o.refine_rotation_weight, nullptr},
      {"loop_search_radius_m", &o.loop_search_radius_m, nullptr},
      {"loop_min_node_gap", nullptr, &o.loop_min_node_gap},
      {"loop_min_chain_distance_m", &o.loop_min_chain_distance_m, nullptr},
      {"loop_submap_half_nodes", nullptr, &o.loop_submap_half_nodes},
      {"loop_search_linear_m", &o.loop_search_linear_m, nullptr},
      {"loop_search_angular_rad", &o.loop_search_angular_rad, nullptr},
      {"loop_min_score", &o.loop_min_score, nullptr},
      {"max_loop_candidates_per_node", nullptr, &o.max_loop_candidates_per_node},
      {"loop_attempt_every_n_nodes", nullptr, &o.loop_attempt_every_n_nodes},
      {"optimize_every_n_nodes", nullptr, &o.optimize_every_n_nodes},
      {"optimizer_max_iterations", nullptr, &o.optimizer_max_iterations},
      {"loop_huber_delta", &o.loop_huber_delta, nullptr},
      {"loop_covariance_scale", &o.loop_covariance_scale, nullptr},
      {"match_covariance_scale", &o.match_covariance_scale, nullptr},
      {"odom_translation_sigma_per_m", &o.odom_translation_sigma_per_m, nullptr},
      {"odom_rotation_sigma_per_rad", &o.odom_rotation_sigma_per_rad, nullptr},
      {"odom_rotation_sigma_per_m", &o.odom_rotation_sigma_per_m, nullptr},
  };
  for (const Field& field : fields) {
    if (name != field.name) continue;
    if (field.real != nullptr) *field.real = value;
    if (field.integer != nullptr) *field.integer = static_cast<int>(value);
    return true;
  }
  return false;
}

void write_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Graph SLAM over a CARMEN log (FLASER / ROBOTLASER1 lines)"};
  std::string log_path, out_dir, gt_path;
  double no_return_range_m = 50.0;
  app.add_option("--carmen", log_path, "CARMEN log, plain or .gz")->required();
  app.add_option("--out", out_dir, "output directory (trajectory.txt, map.pgm, map.yaml)")
      ->required();
  app.add_option("--gt", gt_path, "reference trajectory 't x y theta', one line per laser scan");
  app.add_option("--no-return-range", no_return_range_m,
                 "FLASER readings at or above this (m) mean no return")
      ->capture_default_str();
  std::vector<std::string> overrides;
  app.add_option("--set", overrides, "override a GraphSlamOptions field: name=value (repeatable)");
  CLI11_PARSE(app, argc, argv);
  mobot::slam::GraphSlamOptions options;
  for (const std::string& assignment : overrides) {
    if (!set_option(options, assignment)) {
      std::cerr << "mobot-slam: unknown option or bad value in --set " << assignment << '\n';
      return 2;
    }
  }

  try {
    const std::vector<std::string> lines = mobot::tools::read_text_lines(log_path);
    std::vector<mobot::slam::CarmenLaser> lasers;
    std::size_t malformed = 0;
    for (std::size_t i = 0; i < lines.size(); ++i) {
      mobot::slam::CarmenLine parsed = mobot::slam::parse_carmen_line(lines[i]);
      if (parsed.kind == mobot::slam::CarmenLine::Kind::kMalformed) {
        std::cerr << log_path << ":" << i + 1 << ": " << parsed.error << ", skipped\n";
        ++malformed;
      } else if (parsed.kind == mobot::slam::CarmenLine::Kind::kLaser) {
        lasers.push_back(std::move(*parsed.laser));
      }
    }
    if (lasers.empty()) {
      std::cerr << log_path << ": no laser scans\n";
      return 1;
    }

    const auto start = std::chrono::steady_clock::now();
    mobot::slam::GraphSlam slam(options);
    for (const auto& laser : lasers) {
      // The laser's mounting on the base, from the two logged poses (identity for FLASER logs,
      // whose poses are the laser's).
      const Pose2D sensor_in_base =
          mobot::geometry::compose(mobot::geometry::inverse(laser.odom_pose), laser.laser_pose);
      const bool robot_laser = laser.range_max_m > 0.0F;
      slam.add_scan(mobot::slam::to_laser_scan(laser, no_return_range_m,
                                               robot_laser ? sensor_in_base : Pose2D{}),
                    laser.odom_pose);
    }
    const std::vector<Pose2D> poses = slam.scan_poses();
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    std::filesystem::create_directories(out_dir);
    std::ostringstream trajectory;
    trajectory.precision(9);
    for (std::size_t i = 0; i < poses.size(); ++i) {
      trajectory << lasers[i].timestamp_s << ' ' << poses[i].x << ' ' << poses[i].y << ' '
                 << poses[i].theta << '\n';
    }
    write_file(std::filesystem::path(out_dir) / "trajectory.txt", trajectory.str());
    const mobot::mapping::OccupancyGrid map = slam.render_map();
    const std::vector<std::uint8_t> pgm = mobot::mapping::encode_map_pgm(map);
    write_file(std::filesystem::path(out_dir) / "map.pgm", std::string(pgm.begin(), pgm.end()));
    write_file(std::filesystem::path(out_dir) / "map.yaml",
               mobot::mapping::encode_map_yaml(map, "map.pgm"));

    double t_min = std::numeric_limits<double>::infinity();
    double t_max = -t_min;
    for (const auto& laser : lasers) {
      t_min = std::min(t_min, laser.timestamp_s);
      t_max = std::max(t_max, laser.timestamp_s);
    }
    const double duration_s = t_max - t_min;
    const mobot::slam::SlamStats stats = slam.stats();
    std::printf("scans %zu nodes %zu loop_closures %zu malformed_lines %zu\n", stats.scans,
                stats.nodes, stats.loop_closures, malformed);
    std::printf("log %.1f s wall %.3f s real-time factor %.1f\n", duration_s, wall_s,
                wall_s > 0.0 ? duration_s / wall_s : 0.0);
    std::printf("map %d x %d cells at %.3f m\n", map.width(), map.height(), map.resolution_m());

    if (!gt_path.empty()) {
      const Reference ref = read_reference(gt_path);
      if (ref.positions.size() != poses.size()) {
        std::cerr << gt_path << ": " << ref.positions.size() << " poses for " << poses.size()
                  << " scans\n";
        return 1;
      }
      std::vector<Point2D> estimate;
      estimate.reserve(poses.size());
      for (const auto& p : poses) estimate.push_back({p.x, p.y});
      const auto error = mobot::slam::absolute_trajectory_error(estimate, ref.positions);
      std::printf("ATE %.4f m (max %.4f m over %zu poses)\n", error.ate_rmse_m, error.max_error_m,
                  error.count);
    }
  } catch (const std::exception& e) {
    std::cerr << "mobot-slam: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
