#include "core/estimation/particle_filter/particle_filter_estimator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/kinematics/diff_drive.h"
#include "tests/unit/core/estimation/particle_filter/pf_world.h"

namespace mobot::estimation {
namespace {

using geometry::Pose2D;
using pf_world::position_error;

constexpr double kTrack_m = 0.5;
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

Eigen::Matrix3d diag(double a, double b, double c) { return Eigen::Vector3d(a, b, c).asDiagonal(); }

std::shared_ptr<const MapModel> room_map(const pf_world::Room& room) {
  auto model = std::make_shared<MapModel>();
  model->grid = std::make_shared<const mapping::OccupancyGrid>(pf_world::room_grid(room));
  return model;
}

// The estimator on the robot: wheel travel every tick, a scan every fifth.
class Robot {
 public:
  const pf_world::Room& room() const { return room_; }
  const Pose2D& truth() const { return path_[at_]; }
  bool finished() const { return at_ + 1 >= path_.size(); }
  const WheelTravel& last_travel() const { return travel_; }

  void tick(PoseEstimator& estimator) {
    const Pose2D delta = geometry::compose(geometry::inverse(path_[at_]), path_[at_ + 1]);
    ++at_;
    std::normal_distribution<double> noise(0.0, 0.02);
    const double ds = delta.x * (1.0 + noise(rng_));
    const double dtheta = delta.theta * (1.0 + noise(rng_));
    travel_ = {ds - dtheta * kTrack_m / 2.0, ds + dtheta * kTrack_m / 2.0};
    EstimatorInputs inputs;
    inputs.stamp_s = 0.02 * static_cast<double>(at_);
    inputs.travel = &travel_;
    inputs.track_m = kTrack_m;
    msgs::LaserScan scan;
    if (at_ % 5 == 0) {
      scan = pf_world::room_scan(room_, truth(), &scan_rng_);
      inputs.scan = &scan;
    }
    estimator.update(inputs);
  }

 private:
  pf_world::Room room_ = pf_world::asymmetric_room();
  std::vector<Pose2D> path_ = pf_world::loop_path(2);
  std::size_t at_ = 0;
  std::mt19937_64 rng_{3};
  std::mt19937 scan_rng_{4};
  WheelTravel travel_;
};

TEST(ParticleFilterEstimator, NamesItselfForTheRegistryAndTheRobotStatus) {
  const ParticleFilterEstimator estimator;
  EXPECT_EQ(estimator.name(), "particle_filter");
  EXPECT_EQ(estimator.method(), "particle_filter(laser)");
  EXPECT_EQ(estimator.method().rfind("particle_filter", 0), 0U);
}

TEST(ParticleFilterEstimator, LocalizesOnTheMapAndMovesSmoothlyEveryTick) {
  Robot robot;
  ParticleFilterEstimator estimator;
  estimator.set_map(room_map(robot.room()));
  const Pose2D start{robot.truth().x - 0.2, robot.truth().y + 0.2, robot.truth().theta + 0.1};
  estimator.reset(start, diag(0.04, 0.04, 0.01));
  EXPECT_FALSE(estimator.converged());
  Pose2D last = estimator.pose();
  std::uint64_t updates = 0;
  for (int i = 0; i < 1500 && !robot.finished(); ++i) {
    robot.tick(estimator);
    const Pose2D now = estimator.pose();
    if (estimator.counters().scan_updates == updates) {
      // No update this tick: the pose moved by exactly this tick's wheel travel.
      const Pose2D expected = kinematics::integrate_wheel_travel(
          last, robot.last_travel().left_m, robot.last_travel().right_m, kTrack_m);
      ASSERT_NEAR(now.x, expected.x, 1e-9);
      ASSERT_NEAR(now.y, expected.y, 1e-9);
      ASSERT_NEAR(geometry::wrap_angle(now.theta - expected.theta), 0.0, 1e-9);
    }
    updates = estimator.counters().scan_updates;
    last = now;
  }
  EXPECT_GT(updates, 30U);
  EXPECT_TRUE(estimator.converged());
  EXPECT_LT(position_error(estimator.pose(), robot.truth()), 0.1);
  EXPECT_GT(estimator.counters().features_matched, 30U * updates);
  EXPECT_EQ(estimator.counters().rejected_updates, 0U);
  const Eigen::Matrix3d covariance = estimator.covariance();
  EXPECT_LT(covariance(0, 0), 0.15 * 0.15);
  EXPECT_GT(covariance(0, 0), 0.0);
}

TEST(ParticleFilterEstimator, WithoutAMapItDeadReckonsAndNeverConverges) {
  Robot robot;
  ParticleFilterEstimator estimator;
  const Pose2D start = robot.truth();
  estimator.reset(start, diag(1e-4, 1e-4, 1e-4));
  Pose2D expected = start;
  for (int i = 0; i < 400; ++i) {
    robot.tick(estimator);
    expected = kinematics::integrate_wheel_travel(expected, robot.last_travel().left_m,
                                                  robot.last_travel().right_m, kTrack_m);
    ASSERT_FALSE(estimator.converged());
  }
  EXPECT_NEAR(estimator.pose().x, expected.x, 1e-9);
  EXPECT_NEAR(estimator.pose().y, expected.y, 1e-9);
  EXPECT_GT(estimator.covariance()(0, 0) + estimator.covariance()(1, 1), 1e-3);
  EXPECT_EQ(estimator.counters().scan_updates, 0U);
  EXPECT_FALSE(estimator.start_global_localization());
}

// The map worker prepares the field and free cells with the map; the estimator takes them rather
// than building its own on the control loop, unless they were built for another distance cap.
// (The prepared free space here is the room's west half only, so whose it is shows in the cloud.)
TEST(ParticleFilterEstimator, UsesTheFieldPreparedWithTheMap) {
  Robot robot;
  const mapping::OccupancyGrid room = pf_world::room_grid(robot.room());
  mapping::OccupancyGrid west_half = room;
  for (int y = 0; y < west_half.height(); ++y) {
    for (int x = 0; x < west_half.width(); ++x) {
      if (west_half.cell_center({x, y}).x > 5.0) {
        west_half.set({x, y}, mapping::OccupancyGrid::kOccupied);
      }
    }
  }
  for (const double cap_m : {2.0, 1.5}) {
    auto model = std::make_shared<MapModel>();
    model->grid = std::make_shared<const mapping::OccupancyGrid>(room);
    const ParticleFilterMap prepared =
        prepare_particle_filter_map(west_half, LikelihoodFieldOptions{cap_m});
    model->likelihood_field = prepared.field;
    model->free_space = prepared.free_space;
    ParticleFilterEstimator estimator;  // likelihood_max_distance_m 2 m
    estimator.set_map(model);
    ASSERT_TRUE(estimator.start_global_localization());
    double max_x = -1e9;
    for (const WeightedPose& p : estimator.particles(2000)) max_x = std::max(max_x, p.pose.x);
    if (cap_m == 2.0) {
      EXPECT_LT(max_x, 5.0 + 0.05) << "the prepared free space was not used";
    } else {
      EXPECT_GT(max_x, 9.0) << "a field for another distance cap was used";
    }
  }
}

TEST(ParticleFilterEstimator, GlobalLocalizationSpreadsTheCloudOverTheMap) {
  Robot robot;
  ParticleFilterEstimator estimator;
  estimator.set_map(room_map(robot.room()));
  ASSERT_TRUE(estimator.start_global_localization());
  EXPECT_FALSE(estimator.converged());
  const auto sample = estimator.particles(500);
  ASSERT_EQ(sample.size(), 500U);
  double total = 0.0;
  double min_x = 1e9;
  double max_x = -1e9;
  for (const WeightedPose& p : sample) {
    total += p.weight;
    min_x = std::min(min_x, p.pose.x);
    max_x = std::max(max_x, p.pose.x);
    EXPECT_TRUE(robot.room().free(p.pose.x, p.pose.y));
  }
  EXPECT_NEAR(total, 1.0, 1e-9);
  EXPECT_LT(min_x, 1.0);
  EXPECT_GT(max_x, 9.0);
  EXPECT_TRUE(estimator.particles(0).empty());
  EXPECT_EQ(estimator.particles(100000).size(), estimator.filter().particles().size());
  // The whole cloud's size, not the sample's: the particles topic's total.
  EXPECT_EQ(estimator.particle_count(), estimator.filter().particles().size());
  EXPECT_GT(estimator.particle_count(), sample.size());
}

TEST(ParticleFilterEstimator, BadInputsAreCountedAndChangeNothing) {
  Robot robot;
  ParticleFilterEstimator estimator;
  estimator.set_map(room_map(robot.room()));
  estimator.reset(robot.truth(), diag(0.01, 0.01, 0.01));
  const Pose2D before = estimator.pose();
  const Eigen::Matrix3d covariance_before = estimator.covariance();

  const WheelTravel nan_travel{kNan, 0.1};
  EstimatorInputs inputs;
  inputs.travel = &nan_travel;
  inputs.track_m = kTrack_m;
  estimator.update(inputs);
  const WheelTravel good{0.3, 0.3};
  inputs.travel = &good;
  inputs.track_m = 0.0;
  estimator.update(inputs);
  inputs.track_m = kNan;
  estimator.update(inputs);
  EXPECT_EQ(estimator.counters().rejected_updates, 3U);
  // An empty scan, after the motion that would have triggered an update.
  inputs = {};
  msgs::LaserScan empty;
  inputs.scan = &empty;
  estimator.update(inputs);
  EXPECT_EQ(estimator.counters().rejected_updates, 4U);
  // Refused resets.
  estimator.reset({kNan, 0.0, 0.0}, diag(0.01, 0.01, 0.01));
  estimator.reset(robot.truth(), diag(-1.0, 0.01, 0.01));
  EXPECT_EQ(estimator.counters().rejected_updates, 6U);
  EXPECT_EQ(estimator.pose(), before);
  EXPECT_EQ(estimator.covariance(), covariance_before);
  EXPECT_EQ(estimator.counters().scan_updates, 0U);
  // A null map, or one without cells, removes the map; the same grid again is kept as it is.
  const auto map = room_map(robot.room());
  estimator.set_map(map);
  estimator.set_map(map);
  EXPECT_TRUE(estimator.filter().has_map());
  estimator.set_map(nullptr);
  EXPECT_FALSE(estimator.filter().has_map());
  auto blank = std::make_shared<MapModel>();
  blank->grid = std::make_shared<const mapping::OccupancyGrid>();
  estimator.set_map(blank);
  EXPECT_FALSE(estimator.filter().has_map());
  EXPECT_FALSE(estimator.start_global_localization());
}

}  // namespace
}  // namespace mobot::estimation
