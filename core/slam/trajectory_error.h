#pragma once

#include <cstddef>
#include <span>

#include "core/geometry/pose2d.h"

namespace mobot::slam {

struct TrajectoryError {
  double ate_rmse_m = 0.0;  // RMSE of the aligned positions
  double max_error_m = 0.0;
  std::size_t count = 0;
  // The rigid transform that maps the estimate onto the reference: reference ~ alignment (+) e.
  geometry::Pose2D alignment;
};

// docs/algorithms.md E5: the absolute trajectory error. The estimates are aligned to the reference
// by the least-squares rigid 2D transform (Horn / Umeyama without scale: centroids, then the
// rotation angle atan2(sum e x r, sum e . r) of the centred points), and the position residuals'
// RMSE is returned. Point i of each span is the same instant. Throws std::invalid_argument on a
// size mismatch, no points, or a non-finite point.
TrajectoryError absolute_trajectory_error(std::span<const geometry::Point2D> estimate,
                                          std::span<const geometry::Point2D> reference);

}  // namespace mobot::slam
