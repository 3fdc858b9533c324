#include "core/slam/trajectory_error.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace mobot::slam {
namespace {

std::vector<geometry::Point2D> figure_eight() {
  std::vector<geometry::Point2D> points;
  for (int i = 0; i < 100; ++i) {
    const double t = 0.0628 * i;
    points.push_back({3.0 * std::sin(t), 2.0 * std::sin(t) * std::cos(t)});
  }
  return points;
}

TEST(TrajectoryError, IsZeroForARotatedAndTranslatedCopy) {
  const auto reference = figure_eight();
  const geometry::Pose2D frame{5.0, -2.0, 0.7};
  std::vector<geometry::Point2D> estimate;
  for (const auto& p : reference) estimate.push_back(geometry::transform_point(frame, p));
  const TrajectoryError error = absolute_trajectory_error(estimate, reference);
  EXPECT_NEAR(error.ate_rmse_m, 0.0, 1e-9);
  EXPECT_NEAR(error.max_error_m, 0.0, 1e-9);
  EXPECT_EQ(error.count, reference.size());
  // The alignment undoes the frame.
  const geometry::Pose2D undo = geometry::inverse(frame);
  EXPECT_NEAR(error.alignment.x, undo.x, 1e-9);
  EXPECT_NEAR(error.alignment.y, undo.y, 1e-9);
  EXPECT_NEAR(error.alignment.theta, undo.theta, 1e-9);
}

TEST(TrajectoryError, MeasuresAKnownOffsetPattern) {
  const auto reference = figure_eight();
  // Alternate +-0.1 m along x: no rigid motion removes it, and the RMSE is 0.1 m.
  std::vector<geometry::Point2D> estimate = reference;
  for (std::size_t i = 0; i < estimate.size(); ++i) estimate[i].x += i % 2 == 0 ? 0.1 : -0.1;
  EXPECT_NEAR(absolute_trajectory_error(estimate, reference).ate_rmse_m, 0.1, 0.005);
}

TEST(TrajectoryError, RejectsMismatchedEmptyAndNonFiniteInput) {
  const auto reference = figure_eight();
  auto estimate = reference;
  estimate.pop_back();
  EXPECT_THROW(absolute_trajectory_error(estimate, reference), std::invalid_argument);
  EXPECT_THROW(absolute_trajectory_error({}, {}), std::invalid_argument);
  estimate = reference;
  estimate[3].y = std::nan("");
  EXPECT_THROW(absolute_trajectory_error(estimate, reference), std::invalid_argument);
  // A single point aligns exactly.
  const std::vector<geometry::Point2D> one{{1.0, 2.0}}, other{{3.0, 4.0}};
  EXPECT_NEAR(absolute_trajectory_error(one, other).ate_rmse_m, 0.0, 1e-12);
}

}  // namespace
}  // namespace mobot::slam
