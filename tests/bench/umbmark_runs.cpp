// UMBmark calibration of the simulated R1 (docs/algorithms.md E1, Borenstein & Feng 1996).
//
// The robot drives n clockwise and n counter-clockwise square runs by dead reckoning: a driver
// closes its loop on the robot's own odometry (nominal geometry) and follows a square of side L
// as the odometry sees it, so when the odometry says "back at the start" the robot really stops
// somewhere else. The return-position error (true stop minus the odometry's belief, in the start
// frame) is measured against the simulator's true pose. umbmark_calibrate turns the error
// centroids into E_d and E_b and corrected odometry parameters, which are then checked: the
// squares are run again with the corrected parameters (Borenstein's E_max,syst before/after) and
// a 7 m straight run is driven with both (E1: 3.86 % -> 0.09 % on the source's robot).
//
// Exit status 0 only when the straight-run error after calibration is below 0.5 % and below a
// fifth of the error before; 1 otherwise; 2 on bad arguments.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

#include "core/estimation/umbmark.h"
#include "core/estimation/wheel_odometry.h"
#include "core/mapping/occupancy_grid.h"
#include "drivers/sim/robot_profile.h"
#include "drivers/sim/simulator.h"
#include "drivers/sim/world.h"

namespace {

using mobot::geometry::Point2D;
using mobot::geometry::Pose2D;
using mobot::geometry::wrap_angle;
namespace estimation = mobot::estimation;
namespace mapping = mobot::mapping;
namespace sim = mobot::sim;

constexpr double kPi = std::numbers::pi;
constexpr double kDt_s = 0.02;  // the server's 50 Hz control loop
constexpr double kCruise_mps = 0.3;
constexpr double kCreep_mps = 0.02;
constexpr double kTurnMax_radps = 0.5;
constexpr double kTurnMin_radps = 0.02;
constexpr double kTurnDone_rad = 2e-4;
// A run that has not finished after this long is stuck (it never happens in the open hall).
constexpr double kRunTimeout_s = 600.0;

// An empty 20 x 16 m hall with 0.1 m walls: room for 4 m squares both ways and a 7 m straight run
// from the start at (5, 8) heading +x.
sim::World open_hall() {
  constexpr double kCell_m = 0.05;
  sim::World world;
  world.name = "umbmark_hall";
  world.description = "20 x 16 m empty hall for UMBmark runs";
  const int width = static_cast<int>(std::lround(20.0 / kCell_m));
  const int height = static_cast<int>(std::lround(16.0 / kCell_m));
  world.floor = mapping::OccupancyGrid(width, height, kCell_m, {}, mapping::OccupancyGrid::kFree);
  for (int x = 0; x < width; ++x) {
    for (int y = 0; y < height; ++y) {
      if (x < 2 || y < 2 || x >= width - 2 || y >= height - 2) {
        world.floor.set({x, y}, mapping::OccupancyGrid::kOccupied);
      }
    }
  }
  world.start = {5.0, 8.0, 0.0};
  return world;
}

estimation::OdometryParams nominal_params(const sim::RobotProfile& profile) {
  return {profile.wheel_radius_m, profile.wheel_radius_m, profile.track_m,
          static_cast<int>(profile.ticks_per_wheel_rev)};
}

// Drives the simulated robot along legs and turns using only its dead-reckoned pose.
class OdometryDriver {
 public:
  OdometryDriver(sim::Simulator& robot, const estimation::OdometryParams& params)
      : robot_(robot), odometry_(params, robot.true_pose()) {
    odometry_.update(robot_.read_encoders());
  }

  const Pose2D& believed() const { return odometry_.odometry().pose; }
  bool timed_out() const { return robot_.time_s() > kRunTimeout_s; }

  // Straight from the believed pose `from` along `heading_rad` for length_m, as the odometry
  // measures it: heading and cross-track feedback on the odometry pose, slowing down at the end.
  void leg(Pose2D from, double heading_rad, double length_m) {  // by value: from may be believed()
    const double ux = std::cos(heading_rad);
    const double uy = std::sin(heading_rad);
    while (!timed_out()) {
      const Pose2D& p = believed();
      const double along_m = (p.x - from.x) * ux + (p.y - from.y) * uy;
      const double cross_m = -(p.x - from.x) * uy + (p.y - from.y) * ux;
      const double remaining_m = length_m - along_m;
      if (remaining_m <= 0.0) break;
      const double v = std::clamp(1.5 * remaining_m, kCreep_mps, kCruise_mps);
      // Steer back onto the leg: aim at a point 0.5 m ahead on it.
      const double aim_rad = wrap_angle(heading_rad - std::atan2(cross_m, 0.5) - p.theta);
      const double w = std::clamp(2.0 * aim_rad, -kTurnMax_radps, kTurnMax_radps);
      // Never roll past the end within one tick.
      step({std::min(v, remaining_m / kDt_s), w});
    }
    step({0.0, 0.0});
  }

  // Turns on the spot until the odometry heading reaches heading_rad.
  void turn_to(double heading_rad) {
    while (!timed_out()) {
      const double error_rad = wrap_angle(heading_rad - believed().theta);
      if (std::abs(error_rad) <= kTurnDone_rad) break;
      const double magnitude = std::clamp(2.0 * std::abs(error_rad), kTurnMin_radps,
                                          std::min(kTurnMax_radps, std::abs(error_rad) / kDt_s));
      step({0.0, std::copysign(magnitude, error_rad)});
    }
    step({0.0, 0.0});
  }

 private:
  void step(const mobot::msgs::Twist& command) {
    robot_.set_command(command);
    robot_.step(kDt_s);
    odometry_.update(robot_.read_encoders());
  }

  sim::Simulator& robot_;
  estimation::WheelOdometry odometry_;
};

// A point of the map frame in the frame of `start`.
Point2D in_frame(const Pose2D& start, const Point2D& point) {
  const double dx = point.x - start.x;
  const double dy = point.y - start.y;
  const double c = std::cos(start.theta);
  const double s = std::sin(start.theta);
  return {c * dx + s * dy, -s * dx + c * dy};
}

// One square run; returns the return-position error (true stop minus the odometry's belief) in
// the start frame, or nullopt when the run did not finish (timeout or collision).
std::optional<estimation::UmbmarkRunError> square_run(sim::Simulator& robot,
                                                      const sim::World& world,
                                                      const estimation::OdometryParams& params,
                                                      double side_m, bool clockwise,
                                                      std::uint64_t seed) {
  robot.reset(world.start, seed);
  OdometryDriver driver(robot, params);
  const double turn_rad = clockwise ? -kPi / 2.0 : kPi / 2.0;
  double heading_rad = world.start.theta;
  for (int leg = 0; leg < 4; ++leg) {
    driver.leg(driver.believed(), heading_rad, side_m);
    if (leg < 3) {
      heading_rad = wrap_angle(heading_rad + turn_rad);
      driver.turn_to(heading_rad);
    }
  }
  if (driver.timed_out() || robot.collision_count() > 0) {
    std::fprintf(stderr, "square run (seed %llu) did not complete\n",
                 static_cast<unsigned long long>(seed));
    return std::nullopt;
  }
  const Pose2D truth = robot.true_pose();
  const Point2D true_end = in_frame(world.start, {truth.x, truth.y});
  const Point2D believed_end = in_frame(world.start, {driver.believed().x, driver.believed().y});
  return estimation::UmbmarkRunError{true_end.x - believed_end.x, true_end.y - believed_end.y};
}

// A straight run of length_m driven on odometry; the error in percent of the length, or nullopt
// when the run did not finish.
std::optional<double> straight_run(sim::Simulator& robot, const sim::World& world,
                                   const estimation::OdometryParams& params, double length_m,
                                   std::uint64_t seed) {
  robot.reset(world.start, seed);
  OdometryDriver driver(robot, params);
  driver.leg(driver.believed(), world.start.theta, length_m);
  if (driver.timed_out() || robot.collision_count() > 0) {
    std::fprintf(stderr, "straight run (seed %llu) did not complete\n",
                 static_cast<unsigned long long>(seed));
    return std::nullopt;
  }
  const Pose2D truth = robot.true_pose();
  const Point2D intended{world.start.x + length_m * std::cos(world.start.theta),
                         world.start.y + length_m * std::sin(world.start.theta)};
  return estimation::straight_run_error_percent(intended, {truth.x, truth.y}, length_m);
}

struct SquareSet {
  std::vector<estimation::UmbmarkRunError> cw;
  std::vector<estimation::UmbmarkRunError> ccw;
  int incomplete = 0;
};

SquareSet square_runs(sim::Simulator& robot, const sim::World& world,
                      const estimation::OdometryParams& params, double side_m, int runs,
                      std::uint64_t first_seed) {
  SquareSet set;
  for (int i = 0; i < runs; ++i) {
    const std::uint64_t seed = first_seed + 2 * static_cast<std::uint64_t>(i);
    for (const bool clockwise : {true, false}) {
      const auto error =
          square_run(robot, world, params, side_m, clockwise, clockwise ? seed : seed + 1);
      if (!error) {
        ++set.incomplete;
      } else {
        (clockwise ? set.cw : set.ccw).push_back(*error);
      }
    }
  }
  return set;
}

void print_runs(const char* label, const SquareSet& set) {
  std::printf("%s return errors (x, y) in mm, start frame:\n", label);
  for (std::size_t i = 0; i < set.cw.size(); ++i) {
    std::printf("  run %zu   cw (%+7.1f, %+7.1f)   ccw (%+7.1f, %+7.1f)\n", i + 1,
                1e3 * set.cw[i].x_m, 1e3 * set.cw[i].y_m, 1e3 * set.ccw[i].x_m,
                1e3 * set.ccw[i].y_m);
  }
}

struct StraightResult {
  double mean_percent = 0.0;
  double max_percent = 0.0;
  int incomplete = 0;
};

StraightResult straight_runs(sim::Simulator& robot, const sim::World& world,
                             const estimation::OdometryParams& params, double length_m, int runs,
                             std::uint64_t first_seed) {
  StraightResult result;
  for (int i = 0; i < runs; ++i) {
    const auto percent = straight_run(robot, world, params, length_m, first_seed + i);
    if (!percent) {
      ++result.incomplete;
      result.mean_percent = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    result.mean_percent += *percent / runs;
    result.max_percent = std::max(result.max_percent, *percent);
  }
  return result;
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 5;
  double side_m = 4.0;
  double straight_m = 7.0;
  int straight_runs_n = 5;
  std::uint64_t seed = 1;
  bool show_runs = false;
  CLI::App cli{
      "mobot_umbmark: UMBmark calibration (docs/algorithms.md E1) of the simulated R1.\n"
      "n clockwise and n counter-clockwise squares driven by dead reckoning (a driver closing\n"
      "its loop on the nominal odometry), return errors measured against the true pose, fed to\n"
      "umbmark_calibrate; then the squares again and a 7 m straight run with the nominal and the\n"
      "corrected parameters. Exit 0 only if the straight-run error after is < 0.5 % and less\n"
      "than a fifth of the error before.\n"
      "Command (CI): /work/build-fusion/tests/bench/mobot_umbmark\n"
      "  (same as: mobot_umbmark --runs 5 --side-m 4 --straight-m 7 --straight-runs 5 --seed 1)"};
  cli.add_option("--runs", runs, "square runs per direction")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  cli.add_option("--side-m", side_m, "side of the square")
      ->check(CLI::Range(1.0, 5.0))
      ->capture_default_str();
  cli.add_option("--straight-m", straight_m, "length of the straight run")
      ->check(CLI::Range(1.0, 12.0))
      ->capture_default_str();
  cli.add_option("--straight-runs", straight_runs_n, "straight runs averaged, before and after")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  cli.add_option("--seed", seed, "first seed (every run has its own)")->capture_default_str();
  cli.add_flag("--show-runs", show_runs, "print every square run's return error");
  CLI11_PARSE(cli, argc, argv);

  const auto started = std::chrono::steady_clock::now();
  const sim::World world = open_hall();
  const sim::RobotProfile profile = sim::r1_profile();
  sim::Simulator robot(world, profile, seed);
  const estimation::OdometryParams nominal = nominal_params(profile);

  // Seeds: calibration squares, verification squares and straight runs never share one.
  const std::uint64_t calibration_seed = seed;
  const std::uint64_t verification_seed = seed + 1000;
  const std::uint64_t straight_seed = seed + 2000;

  const SquareSet before = square_runs(robot, world, nominal, side_m, runs, calibration_seed);
  const std::optional<estimation::UmbmarkResult> calibration =
      estimation::umbmark_calibrate(nominal, side_m, before.cw, before.ccw);
  if (!calibration) {
    std::printf("umbmark_calibrate rejected the runs\n");
    return 1;
  }
  const estimation::OdometryParams& corrected = calibration->corrected;
  const SquareSet after = square_runs(robot, world, corrected, side_m, runs, verification_seed);
  const std::optional<estimation::UmbmarkResult> check =
      estimation::umbmark_calibrate(corrected, side_m, after.cw, after.ccw);

  const StraightResult straight_before =
      straight_runs(robot, world, nominal, straight_m, straight_runs_n, straight_seed);
  const StraightResult straight_after =
      straight_runs(robot, world, corrected, straight_m, straight_runs_n, straight_seed);

  const double true_ed = profile.right_wheel_scale / profile.left_wheel_scale;
  const double true_eb = profile.track_scale;
  const double mean_scale = (profile.left_wheel_scale + profile.right_wheel_scale) / 2.0;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto mm = [](double metres) { return 1e3 * metres; };
  std::printf(
      "UMBmark (docs/algorithms.md E1) on the simulated R1: %d cw + %d ccw squares of %.1f m, "
      "driven on odometry at %.2f m/s; seed %llu\n\n",
      runs, runs, side_m, kCruise_mps, static_cast<unsigned long long>(seed));
  if (show_runs) {
    print_runs("nominal parameters:", before);
    print_runs("corrected parameters:", after);
    std::printf("\n");
  }
  std::printf("| quantity                      |  estimated | simulator truth |\n");
  std::printf("|-------------------------------|-----------:|----------------:|\n");
  std::printf("| E_d = D_R / D_L               | %10.6f | %15.6f |\n", calibration->diameter_ratio,
              true_ed);
  std::printf("| E_b = b_actual / b_nominal    | %10.6f | %15.6f |\n",
              calibration->wheelbase_factor, true_eb);
  std::printf("| left radius factor c_L        | %10.6f | %15.6f |\n",
              calibration->left_radius_factor, profile.left_wheel_scale / mean_scale);
  std::printf("| right radius factor c_R       | %10.6f | %15.6f |\n",
              calibration->right_radius_factor, profile.right_wheel_scale / mean_scale);
  std::printf("| alpha (type A, per turn), deg | %10.4f |                 |\n",
              calibration->alpha_rad * 180.0 / kPi);
  std::printf("| beta (type B, per leg), deg   | %10.4f |                 |\n",
              calibration->beta_rad * 180.0 / kPi);
  std::printf(
      "(c_L, c_R truth: the true radii over their mean; UMBmark keeps the mean radius)\n\n");

  std::printf("| result                        |   source | nominal params | corrected params |\n");
  std::printf("|-------------------------------|---------:|---------------:|-----------------:|\n");
  std::printf("| cw c.g. x, y (mm)             |          | %6.1f, %6.1f | %7.1f, %7.1f |\n",
              mm(calibration->cw_centroid.x_m), mm(calibration->cw_centroid.y_m),
              check ? mm(check->cw_centroid.x_m) : nan, check ? mm(check->cw_centroid.y_m) : nan);
  std::printf("| ccw c.g. x, y (mm)            |          | %6.1f, %6.1f | %7.1f, %7.1f |\n",
              mm(calibration->ccw_centroid.x_m), mm(calibration->ccw_centroid.y_m),
              check ? mm(check->ccw_centroid.x_m) : nan, check ? mm(check->ccw_centroid.y_m) : nan);
  std::printf("| E_max,syst (mm)               |          | %14.1f | %16.1f |\n",
              mm(calibration->systematic_error_m), check ? mm(check->systematic_error_m) : nan);
  std::printf("| %4.1f m straight run, mean (%%) | %8.2f | %14.3f | %16.3f |\n", straight_m, 3.86,
              straight_before.mean_percent, straight_after.mean_percent);
  std::printf("| %4.1f m straight run, max (%%)  |          | %14.3f | %16.3f |\n", straight_m,
              straight_before.max_percent, straight_after.max_percent);
  std::printf(
      "(source straight run: 3.86 %% before, 0.09 %% after; %d straight runs each, the "
      "same seeds before and after)\n\n",
      straight_runs_n);

  std::printf("Corrected odometry parameters (estimation::OdometryParams):\n");
  std::printf("odometry:\n");
  std::printf("  left_wheel_radius_m: %.7f    # nominal %.7f\n", corrected.left_wheel_radius_m,
              nominal.left_wheel_radius_m);
  std::printf("  right_wheel_radius_m: %.7f   # nominal %.7f\n", corrected.right_wheel_radius_m,
              nominal.right_wheel_radius_m);
  std::printf("  track_m: %.6f                # nominal %.6f\n", corrected.track_m,
              nominal.track_m);
  std::printf("  ticks_per_wheel_rev: %d\n\n", corrected.ticks_per_wheel_rev);

  const int incomplete =
      before.incomplete + after.incomplete + straight_before.incomplete + straight_after.incomplete;
  if (incomplete > 0) std::printf("%d runs did not complete\n", incomplete);
  const bool pass = incomplete == 0 && straight_after.mean_percent < 0.5 &&
                    straight_after.mean_percent < straight_before.mean_percent / 5.0;
  const double elapsed_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  std::printf("straight-run error after < 0.5 %% and < before / 5: %s; run time %.2f s\n",
              pass ? "PASS" : "FAIL", elapsed_s);
  return pass ? 0 : 1;
}
