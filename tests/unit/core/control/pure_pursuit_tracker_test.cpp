#include "core/control/pure_pursuit_tracker.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "core/kinematics/tricycle.h"
#include "core/kinematics/tricycle_model.h"

namespace mobot::control {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDt = 0.02;  // the control loop's tick

// C3's reference path: 20 m straight along x, then a turn of two half-arcs (radius 5 m, left
// then right), sampled every 0.1 m.
planning::Path reference_path() {
  std::vector<geometry::Point2D> points;
  for (int i = 0; i <= 200; ++i) points.push_back({0.1 * i, 0.0});
  const double r = 5.0;
  for (int i = 1; i <= 157; ++i) {  // left half-arc about (20, 5)
    const double a = -kPi / 2 + kPi * i / 157.0;
    points.push_back({20.0 + r * std::cos(a), 5.0 + r * std::sin(a)});
  }
  for (int i = 1; i <= 157; ++i) {  // right half-arc about (20, 15)
    const double a = -kPi / 2 - kPi * i / 157.0;
    points.push_back({20.0 + r * std::cos(a), 15.0 + r * std::sin(a)});
  }
  return planning::Path(points);
}

double cross_track_m(const planning::Path& path, const geometry::Pose2D& pose) {
  const geometry::Point2D nearest =
      path.point_at(path.project({pose.x, pose.y}, 0.0, path.length_m()));
  return std::hypot(nearest.x - pose.x, nearest.y - pose.y);
}

struct DriveResult {
  double max_cross_track_m = 0.0;  // after the first metres
  bool arrived = false;
  geometry::Pose2D final_pose;
  double max_steer_rad = 0.0;
};

// A tricycle closed around the tracker: the tracker's (v, w) through the kinematic model (R3's
// limits) to (V_c, alpha); the true steering is off by `steer_bias_rad`; RK4 over each tick.
DriveResult drive(kinematics::TricycleType type, const planning::Path& path, geometry::Pose2D start,
          double steer_bias_rad, double seconds = 120.0) {
  kinematics::TricycleModelOptions model_options;
  model_options.geometry.type = type;
  const kinematics::TricycleModel model(model_options);
  PurePursuitOptions options;
  options.max_linear_mps = 1.5;
  options.max_angular_radps = 0.3;
  options.min_turning_radius_m = model.min_turning_radius_m();
  options.goal_tolerance_m = 0.3;
  PurePursuitTracker tracker(options);
  EXPECT_TRUE(tracker.set_path(path, std::nullopt));
  DriveResult run;
  geometry::Pose2D pose = start;
  msgs::Twist velocity;
  for (double t = 0.0; t < seconds; t += kDt) {
    const msgs::Twist command = tracker.compute(pose, velocity, t);
    if (tracker.arrived()) {
      run.arrived = true;
      break;
    }
    msgs::WheelCommand wheels = model.to_wheels(command);
    run.max_steer_rad = std::max(run.max_steer_rad, std::abs(wheels.steering_rad));
    const kinematics::TricycleInput actual{wheels.drive_mps, wheels.steering_rad + steer_bias_rad};
    pose = kinematics::integrate_tricycle_rk4(
        model_options.geometry, pose, [&](double) { return actual; }, t, kDt, kDt);
    velocity = kinematics::tricycle_body_velocity(model_options.geometry, actual);
    if (t > 5.0) run.max_cross_track_m = std::max(run.max_cross_track_m, cross_track_m(path, pose));
  }
  run.final_pose = pose;
  return run;
}

TEST(PurePursuit, FollowsTheReferencePathOnBothTricycles) {
  const planning::Path path = reference_path();
  for (const auto type : {kinematics::TricycleType::kType1, kinematics::TricycleType::kType2}) {
    const DriveResult run = drive(type, path, {0.0, 0.0, 0.0}, 0.0);
    EXPECT_TRUE(run.arrived);
    EXPECT_LT(run.max_cross_track_m, 0.25);
    EXPECT_LE(run.max_steer_rad, kPi / 4 + 1e-9);
  }
}

TEST(PurePursuit, AFiveDegreeSteeringBiasIsCorrectedClosedLoop) {
  const planning::Path path = reference_path();
  const double bias = 5.0 * kPi / 180.0;
  for (const auto type : {kinematics::TricycleType::kType1, kinematics::TricycleType::kType2}) {
    const DriveResult run = drive(type, path, {0.0, 0.0, 0.0}, bias);
    EXPECT_TRUE(run.arrived);
    // The bias leaves a steady offset on the straight (k_needed vs k_biased), not a divergence.
    EXPECT_LT(run.max_cross_track_m, 0.5);
  }
}

TEST(PurePursuit, TheSameBiasBreaksOpenLoopTracking) {
  // Open loop: steer by the path's own curvature at the distance travelled (C3's observation).
  const planning::Path path = reference_path();
  const kinematics::TricycleGeometry geometry;
  const double v = 1.0;
  auto curvature_at = [](double s) {
    if (s < 20.0) return 0.0;
    if (s < 20.0 + 5.0 * kPi) return 0.2;
    return -0.2;
  };
  const double bias = 5.0 * kPi / 180.0;
  geometry::Pose2D pose;
  const double duration = path.length_m() / v;
  for (double t = 0.0; t < duration; t += kDt) {
    const double steer = std::atan(geometry.wheelbase_m * curvature_at(v * t)) + bias;
    pose = kinematics::integrate_tricycle_rk4(
        geometry, pose, [&](double) { return kinematics::TricycleInput{v, steer}; }, t, kDt, kDt);
  }
  EXPECT_GT(std::hypot(pose.x - path.back().x, pose.y - path.back().y), 10.0);
}

TEST(PurePursuit, FallsBackWhenNoLookaheadPointExists) {
  const planning::Path path = reference_path();
  // 6 m beside the path: the look-ahead circle does not reach it; the nearest waypoint ahead
  // leads the robot back, and it still ends at the goal.
  const geometry::Point2D robot{5.0, -6.0};
  EXPECT_EQ(find_lookahead(path, robot, 0.0, 1.5).source, LookaheadSource::kNearestWaypoint);
  // Near the end the rest of the path lies inside the circle: the end itself.
  const LookaheadPoint end = find_lookahead(path, {20.2, 19.9}, path.length_m() - 0.5, 1.5);
  EXPECT_EQ(end.source, LookaheadSource::kPathEnd);
  EXPECT_DOUBLE_EQ(end.point.x, path.back().x);
  const DriveResult run = drive(kinematics::TricycleType::kType2, path, {5.0, -6.0, 0.0}, 0.0);
  EXPECT_TRUE(run.arrived);
}

TEST(PurePursuit, LookaheadPointLiesOnTheCircle) {
  const planning::Path path(std::vector<geometry::Point2D>{{0.0, 0.0}, {10.0, 0.0}});
  const LookaheadPoint p = find_lookahead(path, {1.0, 0.5}, 1.0, 2.0);
  EXPECT_EQ(p.source, LookaheadSource::kCircle);
  EXPECT_NEAR(std::hypot(p.point.x - 1.0, p.point.y - 0.5), 2.0, 1e-9);
  EXPECT_NEAR(p.point.y, 0.0, 1e-12);
}

TEST(PurePursuit, CurvatureFollowsC3AndTurnsHardForAPointBehind) {
  EXPECT_NEAR(pursuit_curvature({0, 0, 0}, {1.0, 1.0}), 2.0 * std::sin(kPi / 4) / std::sqrt(2.0),
              1e-12);
  EXPECT_NEAR(pursuit_curvature({0, 0, 0}, {-1.0, 0.1}), 2.0 / std::hypot(1.0, 0.1), 1e-12);
  EXPECT_LT(pursuit_curvature({0, 0, 0}, {-1.0, -0.1}), 0.0);
}

TEST(PurePursuit, ADifferentialBaseEndsFacingTheGoalHeading) {
  PurePursuitOptions options;
  options.align_heading = true;
  PurePursuitTracker tracker(options);
  ASSERT_TRUE(tracker.set_path(planning::Path(std::vector<geometry::Point2D>{{0, 0}, {3, 0}}),
                               kPi / 2));
  geometry::Pose2D pose;
  for (double t = 0.0; t < 30.0 && !tracker.arrived(); t += kDt) {
    const msgs::Twist cmd = tracker.compute(pose, {}, t);
    pose.theta += cmd.angular_radps * kDt;
    pose.x += cmd.linear_mps * std::cos(pose.theta) * kDt;
    pose.y += cmd.linear_mps * std::sin(pose.theta) * kDt;
  }
  EXPECT_TRUE(tracker.arrived());
  EXPECT_NEAR(pose.theta, kPi / 2, options.goal_tolerance_rad + 1e-9);
  EXPECT_NEAR(pose.x, 3.0, options.goal_tolerance_m + 0.05);
}

TEST(PurePursuit, ACarBacksUpForAGoalInsideItsTurningCircle) {
  PurePursuitOptions options;
  options.min_turning_radius_m = 2.0;
  options.goal_tolerance_m = 0.3;
  PurePursuitTracker tracker(options);
  // The goal 1.5 m to the left: inside the left turning circle.
  ASSERT_TRUE(tracker.set_path(planning::Path(std::vector<geometry::Point2D>{{0, 0}, {0.2, 1.5}}),
                               std::nullopt));
  const msgs::Twist first = tracker.compute({0, 0, 0}, {}, 0.0);
  EXPECT_LT(first.linear_mps, 0.0);
  EXPECT_EQ(first.angular_radps, 0.0);
}

TEST(PurePursuit, BadPathsAndOptionsAreRefused) {
  PurePursuitTracker tracker;
  EXPECT_FALSE(tracker.set_path(planning::Path{}, std::nullopt));
  EXPECT_FALSE(tracker.set_path(planning::Path(std::vector<geometry::Point2D>{{0, 0}, {NAN, 1}}),
                                std::nullopt));
  EXPECT_FALSE(tracker.set_path(planning::Path(std::vector<geometry::Point2D>{{0, 0}, {1, 1}}),
                                std::numeric_limits<double>::infinity()));
  EXPECT_EQ(tracker.status().state, TrackerState::kIdle);
  EXPECT_EQ(tracker.compute({0, 0, 0}, {}, 0.0), msgs::Twist{});
  PurePursuitOptions bad;
  bad.lookahead_max_m = 0.5;  // below the minimum
  EXPECT_THROW(PurePursuitTracker{bad}, std::invalid_argument);
  bad = {};
  bad.min_linear_mps = 5.0;
  EXPECT_THROW(PurePursuitTracker{bad}, std::invalid_argument);
}

}  // namespace
}  // namespace mobot::control
