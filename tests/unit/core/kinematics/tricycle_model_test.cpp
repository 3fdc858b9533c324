#include "core/kinematics/tricycle_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace mobot::kinematics {
namespace {

constexpr double kPi = std::numbers::pi;

TricycleModel model(TricycleType type, bool saturate = true) {
  TricycleModelOptions options;
  options.geometry.type = type;
  options.limits.saturate = saturate;
  return TricycleModel(options);
}

TEST(TricycleModel, WheelsAndBodyRoundTripForBothTypes) {
  for (const auto type : {TricycleType::kType1, TricycleType::kType2}) {
    const TricycleModel m = model(type);
    const msgs::Twist body{0.8, 0.2};
    const msgs::WheelCommand wheels = m.to_wheels(body);
    EXPECT_NEAR(std::tan(wheels.steering_rad), m.options().geometry.wheelbase_m * 0.2 / 0.8, 1e-12);
    const msgs::Twist back = m.to_body(wheels);
    EXPECT_NEAR(back.linear_mps, 0.8, 1e-12);
    EXPECT_NEAR(back.angular_radps, 0.2, 1e-12);
    EXPECT_EQ(wheels.left_radps, 0.0);
    EXPECT_TRUE(m.steered());
  }
  // Type 1 drives the front wheel: faster than the body in a turn.
  EXPECT_GT(model(TricycleType::kType1).to_wheels({0.8, 0.2}).drive_mps, 0.8);
  EXPECT_DOUBLE_EQ(model(TricycleType::kType2).to_wheels({0.8, 0.2}).drive_mps, 0.8);
}

TEST(TricycleModel, FeasibleRespectsSteeringRateAndSpeedLimits) {
  const TricycleModel m = model(TricycleType::kType2);
  // A turn on the spot is impossible: no forward speed, no turn.
  EXPECT_EQ(m.feasible({0.0, 0.5}), msgs::Twist{});
  // Too tight a turn: the steering stops at pi/4 and the speed drops to keep |w| <= 0.3.
  const msgs::Twist tight = m.feasible({1.0, 2.0});
  EXPECT_LE(std::abs(tight.angular_radps), 0.3 + 1e-12);
  EXPECT_NEAR(tight.angular_radps / tight.linear_mps,
              std::tan(kPi / 4) / m.options().geometry.wheelbase_m, 1e-9);
  const msgs::Twist fast = m.feasible({5.0, 0.0});
  EXPECT_NEAR(fast.linear_mps, 1.77, 1e-12);
}

TEST(TricycleModel, SaturationCanBeSwitchedOff) {
  const TricycleModel m = model(TricycleType::kType2, false);
  const msgs::Twist fast = m.feasible({3.0, 0.0});
  EXPECT_DOUBLE_EQ(fast.linear_mps, 3.0);
  EXPECT_NEAR(m.min_turning_radius_m(), m.options().geometry.wheelbase_m, 1e-12);
}

TEST(TricycleModel, NonFiniteCommandsStopAndBadOptionsThrow) {
  const TricycleModel m = model(TricycleType::kType1);
  EXPECT_EQ(m.feasible({NAN, 0.1}), msgs::Twist{});
  const msgs::WheelCommand w = m.to_wheels({0.5, INFINITY});
  EXPECT_EQ(w.drive_mps, 0.0);
  EXPECT_EQ(w.steering_rad, 0.0);
  TricycleModelOptions bad;
  bad.geometry.wheelbase_m = 0.0;
  EXPECT_THROW(TricycleModel{bad}, std::invalid_argument);
  bad = {};
  bad.limits.max_steer_rad = 2.0;
  EXPECT_THROW(TricycleModel{bad}, std::invalid_argument);
}

}  // namespace
}  // namespace mobot::kinematics
