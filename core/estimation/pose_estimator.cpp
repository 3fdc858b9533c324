#include "core/estimation/pose_estimator.h"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace mobot::estimation {

namespace {
constexpr double kConvergedPositionStd_m = 0.15;
constexpr double kConvergedHeadingStd_rad = 0.1;
}  // namespace

bool covariance_converged(const Eigen::Matrix3d& covariance) {
  if (!covariance.allFinite()) return false;
  const Eigen::Matrix2d position = covariance.topLeftCorner<2, 2>();
  // The larger eigenvalue: a cloud long in one direction has not converged, whatever its axes.
  const double largest_var_m2 =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(position, Eigen::EigenvaluesOnly)
          .eigenvalues()
          .maxCoeff();
  return largest_var_m2 < kConvergedPositionStd_m * kConvergedPositionStd_m &&
         covariance(2, 2) < kConvergedHeadingStd_rad * kConvergedHeadingStd_rad;
}

}  // namespace mobot::estimation
