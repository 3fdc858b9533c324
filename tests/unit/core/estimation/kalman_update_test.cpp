#include "core/estimation/kalman_update.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

namespace mobot::estimation {
namespace {

TEST(KalmanUpdate, ScalarHeadingUpdate) {
  MeasurementJacobian h(1, 3);
  h << 0, 0, 1;
  Eigen::MatrixXd r(1, 1);
  r << 1.0;
  Eigen::VectorXd nu(1);
  nu << 1.0;
  const auto c = kalman_update(Eigen::Matrix3d::Identity(), h, r, nu);
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->state_delta(2), 0.5, 1e-12);
  EXPECT_NEAR(c->state_delta(0), 0.0, 1e-12);
  EXPECT_NEAR(c->covariance(2, 2), 0.5, 1e-12);
  EXPECT_NEAR(c->covariance(0, 0), 1.0, 1e-12);
  EXPECT_NEAR(c->nis, 0.5, 1e-12);
}

TEST(KalmanUpdate, JosephFormEqualsTheSimpleFormWithTheOptimalGain) {
  Eigen::Matrix3d p;
  p << 0.5, 0.1, 0.02, 0.1, 0.3, -0.05, 0.02, -0.05, 0.2;
  MeasurementJacobian h(2, 3);
  h << -0.8, -0.6, 0.0, 0.0, 0.0, -1.0;
  Eigen::MatrixXd r(2, 2);
  r << 0.01, 0.001, 0.001, 0.02;
  Eigen::VectorXd nu(2);
  nu << 0.1, -0.05;
  const auto c = kalman_update(p, h, r, nu);
  ASSERT_TRUE(c.has_value());
  const Eigen::MatrixXd s = h * p * h.transpose() + r;
  const Eigen::MatrixXd k = p * h.transpose() * s.inverse();
  const Eigen::Matrix3d simple = (Eigen::Matrix3d::Identity() - k * h) * p;
  EXPECT_TRUE(c->covariance.isApprox(simple, 1e-10));
  EXPECT_TRUE(c->state_delta.isApprox(k * nu, 1e-10));
  EXPECT_TRUE(c->covariance.isApprox(c->covariance.transpose(), 0.0));
}

TEST(KalmanUpdate, RejectsSingularInnovationCovariance) {
  MeasurementJacobian h(1, 3);
  h << 0, 0, 1;
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(1, 1);
  Eigen::VectorXd nu(1);
  nu << 0.1;
  EXPECT_FALSE(kalman_update(Eigen::Matrix3d::Zero(), h, r, nu).has_value());
  EXPECT_FALSE(normalized_innovation_squared(Eigen::Matrix3d::Zero(), h, r, nu).has_value());
}

}  // namespace
}  // namespace mobot::estimation
