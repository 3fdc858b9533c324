// The online SLAM of a mapping session on the simulated Dashgo D1 in the office world, without the
// server: the same tour the API test drives by teleop (along the corridor east, back, down the
// north-south corridor, back to the start), the simulator's noisy and biased odometry and lidar at
// the runtime's rates (control 50 Hz, laser 7 Hz), the graph SLAM with the config's `slam` options.
// Every control tick compares the pose the runtime would report (map -> odom correction of the
// newest matched scan composed with dead reckoning) with the simulator's truth.
//
// Prints the worst and RMS position error over the tour, the final error, the nodes and loop
// closures, and the share of the rendered map's occupied cells within 0.10 m of a wall of the
// world. Exit status 0 when, on every seed, the worst error is under --max-error and the wall share
// at least 95 %; 1 otherwise; 2 on bad arguments.
#include <yaml-cpp/yaml.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "core/estimation/particle_filter/particle_filter.h"
#include "core/estimation/wheel_odometry.h"
#include "core/mapping/occupancy_grid.h"
#include "core/slam/graph_slam.h"
#include "drivers/sim/robot_profile.h"
#include "drivers/sim/simulator.h"
#include "drivers/sim/world.h"
#include "server/plugins/estimator_plugins.h"
#include "server/plugins/slam_options.h"

namespace {

using mobot::geometry::Point2D;
using mobot::geometry::Pose2D;
namespace mapping = mobot::mapping;
namespace sim = mobot::sim;
namespace slam = mobot::slam;

constexpr double kControlRate_hz = 50.0;
constexpr double kDt_s = 1.0 / kControlRate_hz;
constexpr double kLaserRate_hz = 7.0;
constexpr double kPi = std::numbers::pi;

// The API test's teleop tour (tests/api/dashgo_test.cpp), driven on the true pose as an operator
// watching the robot would: turn on the spot, then drive at up to 0.3 m/s.
const std::vector<Point2D> kTour = {{6.0, 7.5},  {12.0, 7.5}, {17.5, 7.5}, {10.0, 7.6},
                                    {10.0, 4.0}, {10.0, 1.5}, {10.0, 7.4}, {2.5, 7.5}};

mobot::msgs::Twist teleop_towards(const Pose2D& truth, const Point2D& target) {
  const double dx = target.x - truth.x;
  const double dy = target.y - truth.y;
  const double heading = std::atan2(dy, dx) - truth.theta;
  const double error = std::atan2(std::sin(heading), std::cos(heading));
  const double w = std::clamp(1.5 * error, -0.5, 0.5);
  const double v = std::abs(error) > 0.4 ? 0.0 : std::min(0.3, 0.6 * std::hypot(dx, dy));
  return {v, w};
}

// Distance from each cell centre to the nearest occupied cell of `walls`, capped at `cap_m`.
bool near_wall(const mapping::OccupancyGrid& walls, Point2D point, double within_m) {
  const int reach = static_cast<int>(std::ceil(within_m / walls.resolution_m()));
  const mapping::CellIndex centre = walls.cell_at_unchecked(point);
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      const mapping::CellIndex cell{centre.x + dx, centre.y + dy};
      if (!walls.contains(cell) || !walls.is_occupied(cell)) continue;
      const Point2D c = walls.cell_center(cell);
      if (std::hypot(c.x - point.x, c.y - point.y) <= within_m + 0.5 * walls.resolution_m()) {
        return true;
      }
    }
  }
  return false;
}

double wall_share(const mapping::OccupancyGrid& map, const mapping::OccupancyGrid& walls) {
  int occupied = 0;
  int near = 0;
  for (int y = 0; y < map.height(); ++y) {
    for (int x = 0; x < map.width(); ++x) {
      if (!map.is_occupied({x, y})) continue;
      ++occupied;
      near += near_wall(walls, map.cell_center({x, y}), 0.10) ? 1 : 0;
    }
  }
  return occupied > 0 ? static_cast<double>(near) / occupied : 0.0;
}

struct TourResult {
  double worst_m = 0.0;
  double rms_m = 0.0;
  double final_m = 0.0;
  double odometry_final_m = 0.0;
  double wall_share = 0.0;
  double slam_s = 0.0;
  double tour_s = 0.0;
  bool completed = false;
  int collisions = 0;
  slam::SlamStats stats;
};

// The simulated Dashgo with the runtime's wheel odometry on its nominal geometry.
struct DashgoRun {
  DashgoRun(const sim::World& world, std::uint64_t seed)
      : robot(world, sim::dashgo_d1_profile(), seed),
        odometry({robot.profile().wheel_radius_m, robot.profile().wheel_radius_m,
                  robot.profile().track_m, static_cast<int>(robot.profile().ticks_per_wheel_rev)},
                 world.start) {
    odometry.update(robot.read_encoders());
  }
  // One control period towards `target`; the odometry pose after it.
  Pose2D step_towards(const Point2D& target) {
    robot.set_command(teleop_towards(robot.true_pose(), target));
    robot.step(kDt_s);
    return odometry.update(robot.read_encoders()).pose;
  }
  bool reached(const Point2D& target) const {
    const Pose2D truth = robot.true_pose();
    return std::hypot(target.x - truth.x, target.y - truth.y) < 0.15;
  }
  sim::Simulator robot;
  mobot::estimation::WheelOdometry odometry;
};

TourResult run_tour(DashgoRun& run, const sim::World& world,
                    const mobot::server::SlamWorkerOptions& options, slam::GraphSlam& mapper,
                    std::uint64_t seed, std::FILE* trace) {
  sim::Simulator& robot = run.robot;
  mapper.set_start_pose(world.start);

  TourResult result;
  double sum_sq = 0.0;
  int samples = 0;
  double next_scan_s = 0.0;
  std::size_t waypoint = 0;
  const double limit_s = 900.0;
  while (waypoint < kTour.size() && robot.time_s() < limit_s) {
    if (run.reached(kTour[waypoint])) {
      ++waypoint;
      continue;
    }
    const Pose2D odom = run.step_towards(kTour[waypoint]);
    if (robot.time_s() >= next_scan_s) {
      next_scan_s += 1.0 / kLaserRate_hz;
      const auto started = std::chrono::steady_clock::now();
      mapper.add_scan(robot.read_laser(), odom);
      result.slam_s +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      if (trace != nullptr) {
        const Pose2D e = mapper.pose();
        const Pose2D truth_now = robot.true_pose();
        std::fprintf(trace, "%llu %.3f %.4f %.4f %.5f %.4f %.4f %.5f %zu %zu\n",
                     static_cast<unsigned long long>(seed), robot.time_s(), truth_now.x,
                     truth_now.y, truth_now.theta, e.x, e.y, e.theta, mapper.stats().nodes,
                     mapper.stats().loop_closures);
      }
    }
    const Pose2D estimate = mobot::geometry::compose(mapper.map_from_odom(), odom);
    const Pose2D now = robot.true_pose();
    const double error_m = std::hypot(estimate.x - now.x, estimate.y - now.y);
    result.worst_m = std::max(result.worst_m, error_m);
    sum_sq += error_m * error_m;
    ++samples;
    result.final_m = error_m;
    result.odometry_final_m = std::hypot(odom.x - now.x, odom.y - now.y);
  }
  result.completed = waypoint == kTour.size();
  result.tour_s = robot.time_s();
  result.collisions = robot.collision_count();
  result.rms_m = samples > 0 ? std::sqrt(sum_sq / samples) : 0.0;
  result.stats = mapper.stats();
  result.wall_share = wall_share(mapper.render_map(options.render), world.floor);
  return result;
}

// One step of the filter towards `target` with the laser at its rate; the outcome.
mobot::estimation::FilterUpdate track_towards(DashgoRun& run,
                                              mobot::estimation::ParticleFilter& filter,
                                              const Point2D& target, double& next_scan_s) {
  const Pose2D odom = run.step_towards(target);
  mobot::msgs::LaserScan scan;
  const bool scanned = run.robot.time_s() >= next_scan_s;
  if (scanned) {
    next_scan_s += 1.0 / kLaserRate_hz;
    scan = run.robot.read_laser();
  }
  return filter.update(odom, scanned ? &scan : nullptr);
}

struct LocalizeResult {
  bool converged = false;
  double converged_after_s = 0.0;  // of driving, from the global start
  double error_at_convergence_m = 0.0;
  Pose2D estimate_at_convergence;
  Pose2D truth_at_convergence;
  double rmse_after_m = 0.0;  // over the ticks after convergence
  double worst_after_m = 0.0;
  std::uint64_t updates = 0;
};

// Global localization on the map the tour made (docs/algorithms.md E4 with the config's
// estimators.particle_filter options): particles over the free space, then up and down the
// corridor the API test drives until the filter reports convergence, and on for `settle_s` to
// measure the error after.
LocalizeResult localize_globally(DashgoRun& run, mobot::estimation::ParticleFilter& filter,
                                 double limit_s, double settle_s) {
  filter.initialize_global(run.odometry.odometry().pose);
  const std::vector<Point2D> route = {{6.0, 7.5}, {2.5, 7.5}};
  LocalizeResult result;
  const double started_s = run.robot.time_s();
  double next_scan_s = started_s;
  double sum_sq = 0.0;
  int samples = 0;
  std::size_t leg = 0;
  while (run.robot.time_s() - started_s < limit_s) {
    if (run.reached(route[leg % route.size()])) {
      ++leg;
      continue;
    }
    track_towards(run, filter, route[leg % route.size()], next_scan_s);
    const Pose2D estimate = filter.pose_at(run.odometry.odometry().pose);
    const Pose2D truth = run.robot.true_pose();
    const double error_m = std::hypot(estimate.x - truth.x, estimate.y - truth.y);
    if (!result.converged && filter.converged()) {
      result.converged = true;
      result.converged_after_s = run.robot.time_s() - started_s;
      result.error_at_convergence_m = error_m;
      result.estimate_at_convergence = estimate;
      result.truth_at_convergence = truth;
    }
    if (result.converged) {
      sum_sq += error_m * error_m;
      ++samples;
      result.worst_after_m = std::max(result.worst_after_m, error_m);
      if (run.robot.time_s() - started_s > result.converged_after_s + settle_s) break;
    }
  }
  result.rmse_after_m = samples > 0 ? std::sqrt(sum_sq / samples) : 0.0;
  result.updates = filter.sensor_updates();
  return result;
}

struct KidnapResult {
  bool recovered = false;
  double recovered_after_s = 0.0;  // of driving after the kidnap, first error under 0.3 m
  double error_at_end_m = 0.0;     // at the end of the drive
  std::uint64_t updates = 0;
};

// The API test's kidnap (tests/api/dashgo_test.cpp step E): the robot, tracked at the corridor's
// west end facing west (where the test's goals leave it), is lifted 11.5 m east along the corridor
// with the same heading, the filter's hardest case (the corridor looks alike along its length), and
// driven up and down there; the filter has to find it again.
KidnapResult recover_from_kidnap(DashgoRun& run, mobot::estimation::ParticleFilter& filter,
                                 double drive_s, std::FILE* trace) {
  double next_scan_s = run.robot.time_s();
  for (const Point2D& target : {Point2D{4.0, 7.5}, Point2D{2.5, 7.5}}) {
    while (!run.reached(target)) track_towards(run, filter, target, next_scan_s);
  }
  run.robot.teleport({14.0, 7.5, run.robot.true_pose().theta});
  const std::vector<Point2D> route = {{10.5, 7.5}, {14.0, 7.5}};
  KidnapResult result;
  const double started_s = run.robot.time_s();
  const std::uint64_t updates_before = filter.sensor_updates();
  std::size_t leg = 0;
  double error_m = 0.0;
  while (run.robot.time_s() - started_s < drive_s) {
    if (run.reached(route[leg % route.size()])) {
      ++leg;
      continue;
    }
    const auto outcome = track_towards(run, filter, route[leg % route.size()], next_scan_s);
    const Pose2D estimate = filter.pose_at(run.odometry.odometry().pose);
    const Pose2D truth = run.robot.true_pose();
    error_m = std::hypot(estimate.x - truth.x, estimate.y - truth.y);
    if (trace != nullptr && outcome == mobot::estimation::FilterUpdate::kUpdated) {
      std::fprintf(trace,
                   "kidnap %.2f error %.3f w_slow %.4f w_fast %.4f random %.3f particles %zu "
                   "estimate %.2f %.2f %.2f\n",
                   run.robot.time_s() - started_s, error_m, filter.w_slow(), filter.w_fast(),
                   filter.last_random_fraction(), filter.particles().size(), estimate.x, estimate.y,
                   estimate.theta);
    }
    if (!result.recovered && error_m < 0.3) {
      result.recovered = true;
      result.recovered_after_s = run.robot.time_s() - started_s;
    }
  }
  result.error_at_end_m = error_m;
  result.updates = filter.sensor_updates() - updates_before;
  return result;
}

// --set name=value: the config's key replaced, for trying a value without editing the file; the
// readers then check it as mobotd would. A dotted name is a path from the config's top
// (estimators.particle_filter.z_rand), a plain one a key of its slam section. False for a
// malformed assignment.
bool set_config_key(YAML::Node& config, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) return false;
  std::string name = assignment.substr(0, eq);
  if (name.find('.') == std::string::npos) name = "slam." + name;
  std::vector<YAML::Node> path = {config};
  std::size_t start = 0;
  for (std::size_t dot = name.find('.'); dot != std::string::npos; dot = name.find('.', start)) {
    if (dot == start) return false;
    path.push_back(path.back()[name.substr(start, dot - start)]);
    start = dot + 1;
  }
  if (start == name.size()) return false;
  path.back()[name.substr(start)] = assignment.substr(eq + 1);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Online graph SLAM on the simulated Dashgo office tour, against the truth"};
  std::string world_path = std::string(MOBOT_SOURCE_ROOT) + "/drivers/sim/worlds/office/world.yaml";
  std::string config_path = std::string(MOBOT_SOURCE_ROOT) + "/deploy/config/dashgo_d1.yaml";
  int seeds = 3;
  std::uint64_t first_seed = 1;
  double max_error_m = 0.10;
  app.add_option("--world", world_path, "world YAML");
  app.add_option("--config", config_path, "mobotd config whose slam section is used");
  app.add_option("--seeds", seeds, "how many seeds")->check(CLI::Range(1, 100));
  app.add_option("--first-seed", first_seed, "the first seed");
  app.add_option("--max-error", max_error_m, "worst position error allowed (m)");
  std::string trace_path;
  app.add_option("--trace", trace_path,
                 "write 'seed t truth_x truth_y truth_theta slam_x slam_y slam_theta nodes loops' "
                 "per scan to this file");
  std::vector<std::string> assignments;
  app.add_option("--set", assignments,
                 "name=value of a config key: a slam key, or a dotted path (repeatable)");
  bool localize = false;
  double localize_limit_s = 120.0;
  app.add_flag("--localize", localize,
               "after the tour, localize globally on its map while driving the corridor "
               "(PASS also needs convergence within --localize-limit with the error under 0.15 m)");
  bool on_floor_plan = false;
  app.add_flag("--on-floor-plan", on_floor_plan,
               "localize on the world's floor plan instead of the tour's map (map errors apart)");
  app.add_option("--localize-limit", localize_limit_s, "seconds of driving allowed to converge");
  bool kidnap = false;
  double kidnap_drive_s = 45.0;
  app.add_flag("--kidnap", kidnap,
               "after global localization (implies --localize), carry the robot off to the "
               "corridor's east part and drive it there (PASS also needs the error under 0.3 m "
               "within 30 s and at the end of --kidnap-drive)");
  app.add_option("--kidnap-drive", kidnap_drive_s, "seconds of driving after the kidnap");
  CLI11_PARSE(app, argc, argv);

  try {
    const sim::World world = sim::load_world(world_path);
    YAML::Node config = YAML::LoadFile(config_path);
    for (const std::string& assignment : assignments) {
      if (!set_config_key(config, assignment)) {
        std::fprintf(stderr, "mobot_slam_office_tour: --set %s: expected name=value\n",
                     assignment.c_str());
        return 2;
      }
    }
    const mobot::server::SlamWorkerOptions options = mobot::server::read_slam_options(config);
    const mobot::estimation::ParticleFilterOptions filter_options =
        mobot::server::read_particle_filter_options(config["estimators"]["particle_filter"]);
    std::FILE* trace = trace_path.empty() ? nullptr : std::fopen(trace_path.c_str(), "w");
    if (!trace_path.empty() && trace == nullptr) {
      std::fprintf(stderr, "mobot_slam_office_tour: cannot write %s\n", trace_path.c_str());
      return 2;
    }
    bool pass = true;
    std::printf(
        "seed  worst_m  rms_m  final_m  odom_final_m  nodes  loops  walls  slam_s  tour_s\n");
    for (int k = 0; k < seeds; ++k) {
      const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(k);
      DashgoRun run(world, seed);
      slam::GraphSlam mapper(options.slam);
      const TourResult r = run_tour(run, world, options, mapper, seed, trace);
      std::printf("%4llu  %7.3f  %5.3f  %7.3f  %12.3f  %5zu  %5zu  %5.3f  %6.2f  %6.1f%s\n",
                  static_cast<unsigned long long>(seed), r.worst_m, r.rms_m, r.final_m,
                  r.odometry_final_m, r.stats.nodes, r.stats.loop_closures, r.wall_share, r.slam_s,
                  r.tour_s, r.completed ? "" : "  (tour not completed)");
      pass = pass && r.completed && r.collisions == 0 && r.worst_m < max_error_m &&
             r.wall_share >= 0.95;
      if (localize || kidnap) {
        // The filter of the global localization goes on to the kidnap.
        mobot::estimation::ParticleFilterOptions seeded = filter_options;
        seeded.seed = seed;
        mobot::estimation::ParticleFilter filter(seeded);
        filter.set_map(mobot::estimation::prepare_particle_filter_map(
            on_floor_plan ? world.floor : mapper.render_map(options.render), seeded.field));
        const LocalizeResult l = localize_globally(run, filter, localize_limit_s, 30.0);
        std::printf(
            "      global localization: %s after %.1f s of driving (%llu updates), error "
            "then %.3f m, over the next 30 s RMSE %.3f m, worst %.3f m\n",
            l.converged ? "converged" : "NOT converged", l.converged_after_s,
            static_cast<unsigned long long>(l.updates), l.error_at_convergence_m, l.rmse_after_m,
            l.worst_after_m);
        if (l.converged) {
          std::printf("      at convergence: estimate %.2f %.2f %.2f, truth %.2f %.2f %.2f\n",
                      l.estimate_at_convergence.x, l.estimate_at_convergence.y,
                      l.estimate_at_convergence.theta, l.truth_at_convergence.x,
                      l.truth_at_convergence.y, l.truth_at_convergence.theta);
        }
        pass = pass && l.converged && l.error_at_convergence_m < 0.15 && l.worst_after_m < 0.15;
        if (kidnap && l.converged) {
          const KidnapResult kid = recover_from_kidnap(run, filter, kidnap_drive_s, trace);
          std::printf(
              "      kidnap: %s after %.1f s of driving, error at the end of %.0f s "
              "%.3f m (%llu updates)\n",
              kid.recovered ? "recovered" : "NOT recovered", kid.recovered_after_s, kidnap_drive_s,
              kid.error_at_end_m, static_cast<unsigned long long>(kid.updates));
          pass = pass && kid.recovered && kid.recovered_after_s <= 30.0 && kid.error_at_end_m < 0.3;
        }
      }
    }
    if (trace != nullptr) std::fclose(trace);
    std::printf("%s\n", pass ? "PASS" : "FAIL");
    return pass ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mobot_slam_office_tour: %s\n", e.what());
    return 2;
  }
}
