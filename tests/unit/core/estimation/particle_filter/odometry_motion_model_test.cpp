#include "core/estimation/particle_filter/odometry_motion_model.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace mobot::estimation {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(OdometryMotionModel, SplitsTheStepAndScalesTheNoiseAsAmclDiffCorrected) {
  const OdometryMotionModel model;  // alphas 0.2
  const OdometryStep step =
      model.step({1.0, 1.0, 0.5}, {1.0 + 0.4 * std::cos(0.6), 1.0 + 0.4 * std::sin(0.6), 0.8});
  EXPECT_NEAR(step.trans_m, 0.4, 1e-12);
  EXPECT_NEAR(step.rot1_rad, 0.1, 1e-12);
  EXPECT_NEAR(step.rot2_rad, 0.2, 1e-12);
  // sigma = sqrt(alpha1 rot^2 + alpha2 trans^2), sqrt(alpha3 trans^2 + alpha4 (rot1^2 + rot2^2)).
  EXPECT_NEAR(step.rot1_sigma_rad, std::sqrt(0.2 * 0.01 + 0.2 * 0.16), 1e-12);
  EXPECT_NEAR(step.trans_sigma_m, std::sqrt(0.2 * 0.16 + 0.2 * (0.01 + 0.04)), 1e-12);
  EXPECT_NEAR(step.rot2_sigma_rad, std::sqrt(0.2 * 0.04 + 0.2 * 0.16), 1e-12);
}

TEST(OdometryMotionModel, DrivingBackwardsIsNotTwoHalfTurnsOfNoise) {
  const OdometryMotionModel model;
  const OdometryStep step = model.step({0.0, 0.0, 0.0}, {-0.3, 0.0, 0.0});
  EXPECT_NEAR(std::abs(step.rot1_rad), kPi, 1e-12);
  EXPECT_NEAR(std::abs(geometry::wrap_angle(step.rot1_rad + step.rot2_rad)), 0.0, 1e-12);
  // The rotation noise comes from translation only, as if driving forwards.
  EXPECT_NEAR(step.rot1_sigma_rad, std::sqrt(0.2 * 0.09), 1e-12);
  EXPECT_NEAR(step.trans_sigma_m, std::sqrt(0.2 * 0.09), 1e-12);
}

TEST(OdometryMotionModel, ATurnOnTheSpotHasNoDirectionOfTravel) {
  const OdometryMotionModel model;
  const OdometryStep step = model.step({2.0, 3.0, 1.0}, {2.005, 3.0, 1.5});
  EXPECT_EQ(step.rot1_rad, 0.0);
  EXPECT_NEAR(step.rot2_rad, 0.5, 1e-12);
  // A step of nothing is sampled as nothing.
  std::mt19937_64 rng(3);
  const OdometryStep none = model.step({2.0, 3.0, 1.0}, {2.0, 3.0, 1.0});
  const geometry::Pose2D moved = model.sample(none, {5.0, 6.0, 0.25}, rng);
  EXPECT_EQ(moved, (geometry::Pose2D{5.0, 6.0, 0.25}));
}

// The exact first and second moments of x' = x + T cos(theta + R1), y' = y + T sin(theta + R1),
// theta' = theta + R1 + R2 with independent Gaussian R1, T, R2 (E[cos(a + n)] = cos(a) e^(-s^2/2),
// E[n cos(a + n)] = -s^2 sin(a) e^(-s^2/2) by Stein's lemma).
struct Moments {
  Eigen::Vector3d mean;
  Eigen::Matrix3d covariance;
};

Moments analytical(const OdometryStep& step, const geometry::Pose2D& pose) {
  const double a = pose.theta + step.rot1_rad;
  const double s1 = step.rot1_sigma_rad;
  const double e1 = std::exp(-s1 * s1 / 2.0);
  const double e4 = std::exp(-2.0 * s1 * s1);
  const double t = step.trans_m;
  const double t2 = t * t + step.trans_sigma_m * step.trans_sigma_m;
  const double mx = t * std::cos(a) * e1;
  const double my = t * std::sin(a) * e1;
  Moments m;
  m.mean = {pose.x + mx, pose.y + my, pose.theta + step.rot1_rad + step.rot2_rad};
  m.covariance(0, 0) = t2 * (1.0 + std::cos(2.0 * a) * e4) / 2.0 - mx * mx;
  m.covariance(1, 1) = t2 * (1.0 - std::cos(2.0 * a) * e4) / 2.0 - my * my;
  m.covariance(0, 1) = m.covariance(1, 0) = t2 * std::sin(2.0 * a) * e4 / 2.0 - mx * my;
  m.covariance(2, 2) = s1 * s1 + step.rot2_sigma_rad * step.rot2_sigma_rad;
  m.covariance(0, 2) = m.covariance(2, 0) = -t * s1 * s1 * std::sin(a) * e1;
  m.covariance(1, 2) = m.covariance(2, 1) = t * s1 * s1 * std::cos(a) * e1;
  return m;
}

TEST(OdometryMotionModel, SampleMomentsMatchTheAnalyticalOnes) {
  OdometryMotionModelOptions options;
  options.alpha1 = 0.1;
  options.alpha2 = 0.3;
  options.alpha3 = 0.2;
  options.alpha4 = 0.05;
  const OdometryMotionModel model(options);
  const geometry::Pose2D pose{1.0, -2.0, 0.7};
  const OdometryStep step = model.step({0.0, 0.0, 0.0}, {0.5, 0.2, 0.45});
  const Moments expected = analytical(step, pose);

  std::mt19937_64 rng(11);
  constexpr int kSamples = 400000;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum_sq = Eigen::Matrix3d::Zero();
  for (int i = 0; i < kSamples; ++i) {
    const geometry::Pose2D p = model.sample(step, pose, rng);
    // Heading about the expected mean, unwrapped (the spread is far below pi).
    const Eigen::Vector3d v(p.x, p.y,
                            expected.mean.z() + geometry::wrap_angle(p.theta - expected.mean.z()));
    sum += v;
    sum_sq += v * v.transpose();
  }
  const Eigen::Vector3d mean = sum / kSamples;
  const Eigen::Matrix3d covariance = sum_sq / kSamples - mean * mean.transpose();
  for (int i = 0; i < 3; ++i) {
    const double standard_error = std::sqrt(expected.covariance(i, i) / kSamples);
    EXPECT_NEAR(mean(i), expected.mean(i), 5.0 * standard_error) << "mean " << i;
    for (int j = 0; j < 3; ++j) {
      // A few per cent of the scale of the entry: far below the size of the entries themselves.
      const double scale = std::sqrt(expected.covariance(i, i) * expected.covariance(j, j));
      EXPECT_NEAR(covariance(i, j), expected.covariance(i, j), 0.02 * scale)
          << "covariance " << i << "," << j;
    }
  }
  // The noise is not negligible here: the mean falls short of the noise-free motion.
  EXPECT_LT(std::hypot(expected.mean.x() - pose.x, expected.mean.y() - pose.y), step.trans_m);
}

TEST(OdometryMotionModel, ZeroAlphasAreDeterministicDeadReckoning) {
  const OdometryMotionModel model({0.0, 0.0, 0.0, 0.0});
  std::mt19937_64 rng(5);
  const geometry::Pose2D before{0.5, 0.5, 0.3};
  const geometry::Pose2D after{1.1, 0.9, -0.4};
  const geometry::Pose2D particle{4.0, 4.0, 1.0};
  const geometry::Pose2D moved = model.sample(model.step(before, after), particle, rng);
  // The particle moves by the same body-frame increment as the odometry.
  const geometry::Pose2D expected =
      geometry::compose(particle, geometry::compose(geometry::inverse(before), after));
  EXPECT_NEAR(moved.x, expected.x, 1e-12);
  EXPECT_NEAR(moved.y, expected.y, 1e-12);
  EXPECT_NEAR(moved.theta, expected.theta, 1e-12);
}

TEST(OdometryMotionModel, RefusesBadAlphasAndPropagatesNonFiniteSteps) {
  EXPECT_THROW(OdometryMotionModel({-0.1, 0.2, 0.2, 0.2}), std::invalid_argument);
  EXPECT_THROW(OdometryMotionModel({0.2, std::numeric_limits<double>::quiet_NaN(), 0.2, 0.2}),
               std::invalid_argument);
  EXPECT_THROW(OdometryMotionModel({0.2, 0.2, 0.2, std::numeric_limits<double>::infinity()}),
               std::invalid_argument);
  const OdometryMotionModel model;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const OdometryStep step = model.step({0.0, 0.0, 0.0}, {nan, 0.0, 0.0});
  EXPECT_FALSE(std::isfinite(step.trans_m));
}

}  // namespace
}  // namespace mobot::estimation
