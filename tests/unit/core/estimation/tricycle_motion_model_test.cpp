#include "core/estimation/tricycle_motion_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace mobot::estimation {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kWheelbase = 1.8439088914585775;

TEST(TricycleMotionModel, StraightAndTurning) {
  const auto straight = tricycle_step({0, 0, 0}, 1.0, 0.0, kWheelbase, 0.1);
  EXPECT_NEAR(straight.x, 0.1, 1e-12);
  EXPECT_NEAR(straight.theta, 0.0, 1e-12);
  const auto turning = tricycle_step({0, 0, 0}, 1.0, kPi / 6, kWheelbase, 0.1);
  EXPECT_NEAR(turning.theta, 0.1 * std::tan(kPi / 6) / kWheelbase, 1e-12);
}

TEST(TricycleMotionModel, MidpointFollowsTheArc) {
  // Constant steering drives a circle of radius d / tan(alpha): after 10 s the midpoint steps
  // end far nearer the exact pose than the Euler steps.
  const double alpha = kPi / 6;
  const double radius = kWheelbase / std::tan(alpha);
  geometry::Pose2D euler;
  geometry::Pose2D midpoint;
  for (int k = 0; k < 100; ++k) {
    euler = tricycle_step(euler, 1.0, alpha, kWheelbase, 0.1, TricycleIntegration::kEuler);
    midpoint = tricycle_step(midpoint, 1.0, alpha, kWheelbase, 0.1, TricycleIntegration::kMidpoint);
  }
  const double heading = 10.0 / radius;
  const geometry::Point2D exact{radius * std::sin(heading), radius * (1 - std::cos(heading))};
  const double euler_error = std::hypot(euler.x - exact.x, euler.y - exact.y);
  const double midpoint_error = std::hypot(midpoint.x - exact.x, midpoint.y - exact.y);
  EXPECT_NEAR(midpoint.theta, geometry::wrap_angle(heading), 1e-9);
  EXPECT_LT(midpoint_error, 1e-3);
  EXPECT_GT(euler_error, 0.05);
}

TEST(TricycleMotionModel, JacobiansMatchFiniteDifferences) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> pos(-5.0, 5.0);
  std::uniform_real_distribution<double> ang(-kPi, kPi);
  std::uniform_real_distribution<double> speed(-1.7, 1.7);
  std::uniform_real_distribution<double> steer(-kPi / 4, kPi / 4);
  const double h = 1e-6;
  const double dt = 0.1;
  for (int trial = 0; trial < 200; ++trial) {
    const TricycleIntegration mode =
        trial % 2 == 0 ? TricycleIntegration::kEuler : TricycleIntegration::kMidpoint;
    const geometry::Pose2D pose{pos(rng), pos(rng), trial % 3 == 0 ? kPi - 1e-3 : ang(rng)};
    const double v = speed(rng);
    const double a = steer(rng);
    const TricycleJacobians j = tricycle_jacobians(pose, v, a, kWheelbase, dt, mode);
    auto column = [](const geometry::Pose2D& p, const geometry::Pose2D& m) {
      return Eigen::Vector3d((p.x - m.x) / (2e-6), (p.y - m.y) / (2e-6),
                             geometry::wrap_angle(p.theta - m.theta) / (2e-6));
    };
    for (int i = 0; i < 3; ++i) {
      geometry::Pose2D plus = pose;
      geometry::Pose2D minus = pose;
      (i == 0 ? plus.x : i == 1 ? plus.y : plus.theta) += h;
      (i == 0 ? minus.x : i == 1 ? minus.y : minus.theta) -= h;
      const Eigen::Vector3d numeric = column(tricycle_step(plus, v, a, kWheelbase, dt, mode),
                                             tricycle_step(minus, v, a, kWheelbase, dt, mode));
      EXPECT_TRUE(j.a.col(i).isApprox(numeric, 1e-6)) << trial << " state " << i;
    }
    const Eigen::Vector3d by_speed = column(tricycle_step(pose, v + h, a, kWheelbase, dt, mode),
                                            tricycle_step(pose, v - h, a, kWheelbase, dt, mode));
    const Eigen::Vector3d by_steer = column(tricycle_step(pose, v, a + h, kWheelbase, dt, mode),
                                            tricycle_step(pose, v, a - h, kWheelbase, dt, mode));
    EXPECT_LT((j.w.col(0) - by_speed).norm(), 1e-6) << trial;
    EXPECT_LT((j.w.col(1) - by_steer).norm(), 1e-6) << trial;
  }
}

}  // namespace
}  // namespace mobot::estimation
