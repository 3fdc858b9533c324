#include "core/estimation/landmark_measurement_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace mobot::estimation {
namespace {

constexpr double kPi = std::numbers::pi;

template <typename Predict>
Eigen::RowVector3d numeric_jacobian(Predict predict, const geometry::Pose2D& pose, bool angle) {
  const double h = 1e-6;
  Eigen::RowVector3d j;
  for (int i = 0; i < 3; ++i) {
    geometry::Pose2D plus = pose;
    geometry::Pose2D minus = pose;
    (i == 0 ? plus.x : i == 1 ? plus.y : plus.theta) += h;
    (i == 0 ? minus.x : i == 1 ? minus.y : minus.theta) -= h;
    const double d = predict(plus)->z - predict(minus)->z;
    j(i) = (angle ? geometry::wrap_angle(d) : d) / (2 * h);
  }
  return j;
}

TEST(LandmarkMeasurementModel, BearingAndRangeValues) {
  const auto b = predict_bearing({1.0, 1.0, kPi / 2}, {2.0, 2.0});
  ASSERT_TRUE(b.has_value());
  EXPECT_NEAR(b->z, -kPi / 4, 1e-12);
  const auto r = predict_range({1.0, 1.0, 0.0}, {4.0, 5.0});
  ASSERT_TRUE(r.has_value());
  EXPECT_NEAR(r->z, 5.0, 1e-12);
}

TEST(LandmarkMeasurementModel, JacobiansMatchFiniteDifferences) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> pos(-5.0, 5.0);
  std::uniform_real_distribution<double> ang(-kPi, kPi);
  for (int trial = 0; trial < 300; ++trial) {
    const geometry::Point2D landmark{pos(rng), pos(rng)};
    geometry::Pose2D pose{pos(rng), pos(rng), ang(rng)};
    if (trial % 5 == 0) {
      // Landmark straight behind: the bearing sits on the +-pi wrap.
      pose.theta = std::atan2(landmark.y - pose.y, landmark.x - pose.x) + kPi + 1e-7;
    }
    if (std::hypot(landmark.x - pose.x, landmark.y - pose.y) < 0.1) continue;
    const auto bearing = [&](const geometry::Pose2D& p) { return predict_bearing(p, landmark); };
    const auto range = [&](const geometry::Pose2D& p) { return predict_range(p, landmark); };
    EXPECT_TRUE(bearing(pose)->h.isApprox(numeric_jacobian(bearing, pose, true), 1e-6)) << trial;
    EXPECT_TRUE(range(pose)->h.isApprox(numeric_jacobian(range, pose, false), 1e-6)) << trial;
  }
}

TEST(LandmarkMeasurementModel, UndefinedOnTheLandmark) {
  EXPECT_FALSE(predict_bearing({1.0, 2.0, 0.0}, {1.0, 2.0}).has_value());
  EXPECT_FALSE(predict_range({1.0, 2.0, 0.0}, {1.0, 2.0}).has_value());
}

}  // namespace
}  // namespace mobot::estimation
