#include "core/kinematics/tricycle.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace mobot::kinematics {
namespace {

constexpr double kPi = std::numbers::pi;

struct Reference {
  TricycleType type;
  std::function<TricycleInput(double)> input;
  double x_m, y_m, theta_rad;
};

// docs/algorithms.md C3: the final poses after 30 s from (0, 0, 0), no saturation, RK4.
TEST(Tricycle, ReproducesTheSixReferenceFinalPoses) {
  const auto constant = [](double) { return TricycleInput{1.0, kPi / 6.0}; };
  const auto steering_ramp = [](double t) { return TricycleInput{1.0, kPi / 6.0 - 0.05 * t}; };
  const auto both_ramps = [](double t) {
    return TricycleInput{1.0 + 0.1 * t, kPi / 6.0 - 0.05 * t};
  };
  const Reference references[] = {
      {TricycleType::kType1, constant, 3.069, 4.079, 8.135},
      {TricycleType::kType2, constant, 0.100, 6.386, 9.393},
      {TricycleType::kType1, steering_ramp, 10.863, 11.329, -3.319},
      {TricycleType::kType2, steering_ramp, 8.676, 13.519, -4.729},
      {TricycleType::kType1, both_ramps, 8.071, 23.524, -13.916},
      {TricycleType::kType2, both_ramps, 4.914, 25.139, -19.299},
  };
  for (const Reference& reference : references) {
    const geometry::Pose2D end = integrate_tricycle_rk4({reference.type}, {}, reference.input,
                                                        0.0, 30.0, 0.01);
    // The source prints three decimals.
    EXPECT_NEAR(end.x, reference.x_m, 1e-3) << reference.x_m;
    EXPECT_NEAR(end.y, reference.y_m, 1e-3) << reference.y_m;
    EXPECT_NEAR(end.theta, reference.theta_rad, 1e-3) << reference.theta_rad;
  }
}

TEST(Tricycle, AConstantInputDrivesACircleOfRadiusDOverTanAlphaForType2) {
  const TricycleGeometry geometry{TricycleType::kType2};
  const msgs::Twist body = tricycle_body_velocity(geometry, {1.0, kPi / 6.0});
  EXPECT_NEAR(body.linear_mps / body.angular_radps, 3.194, 5e-4);
  // Every pose of the run lies on that circle about (0, R).
  const double radius_m = geometry.wheelbase_m / std::tan(kPi / 6.0);
  for (const double t_s : {1.0, 5.0, 12.5, 30.0}) {
    const geometry::Pose2D pose = integrate_tricycle_rk4(
        geometry, {}, [](double) { return TricycleInput{1.0, kPi / 6.0}; }, 0.0, t_s, 0.01);
    EXPECT_NEAR(std::hypot(pose.x, pose.y - radius_m), radius_m, 1e-6) << t_s;
  }
}

TEST(Tricycle, Type1TurnsOnTheSpotWithItsWheelAcross) {
  const msgs::Twist type1 = tricycle_body_velocity({TricycleType::kType1}, {1.0, kPi / 2.0});
  EXPECT_NEAR(type1.linear_mps, 0.0, 1e-12);
  EXPECT_GT(type1.angular_radps, 0.5);
}

TEST(Tricycle, SaturationKeepsTheCurvatureAndEveryLimit) {
  const TricycleGeometry geometry{TricycleType::kType2};
  const TricycleLimits limits;
  const TricycleInput wild{5.0, 1.2};
  const TricycleInput saturated = saturate(geometry, limits, wild);
  EXPECT_NEAR(saturated.steer_rad, kPi / 4.0, 1e-12);
  const msgs::Twist body = tricycle_body_velocity(geometry, saturated);
  EXPECT_LE(std::abs(body.linear_mps), limits.max_linear_mps + 1e-12);
  EXPECT_LE(std::abs(body.angular_radps), limits.max_angular_radps + 1e-12);
  // The turn the clamped steering asks for is kept: w / v = tan(alpha) / d.
  EXPECT_NEAR(body.angular_radps / body.linear_mps, std::tan(kPi / 4.0) / geometry.wheelbase_m,
              1e-12);
  // Switched off, the input passes as it is.
  const TricycleInput raw = saturate(geometry, {.saturate = false}, wild);
  EXPECT_EQ(raw.drive_mps, wild.drive_mps);
  EXPECT_EQ(raw.steer_rad, wild.steer_rad);
}

}  // namespace
}  // namespace mobot::kinematics
