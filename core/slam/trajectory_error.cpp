#include "core/slam/trajectory_error.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mobot::slam {

TrajectoryError absolute_trajectory_error(std::span<const geometry::Point2D> estimate,
                                          std::span<const geometry::Point2D> reference) {
  if (estimate.size() != reference.size() || estimate.empty()) {
    throw std::invalid_argument("absolute_trajectory_error: sizes differ or no points");
  }
  const std::size_t n = estimate.size();
  double ex = 0.0, ey = 0.0, rx = 0.0, ry = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& e = estimate[i];
    const auto& r = reference[i];
    if (!std::isfinite(e.x) || !std::isfinite(e.y) || !std::isfinite(r.x) || !std::isfinite(r.y)) {
      throw std::invalid_argument("absolute_trajectory_error: non-finite point");
    }
    ex += e.x;
    ey += e.y;
    rx += r.x;
    ry += r.y;
  }
  const double inv_n = 1.0 / static_cast<double>(n);
  ex *= inv_n;
  ey *= inv_n;
  rx *= inv_n;
  ry *= inv_n;
  double dot = 0.0, cross = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double ax = estimate[i].x - ex, ay = estimate[i].y - ey;
    const double bx = reference[i].x - rx, by = reference[i].y - ry;
    dot += ax * bx + ay * by;
    cross += ax * by - ay * bx;
  }
  const double theta = (dot == 0.0 && cross == 0.0) ? 0.0 : std::atan2(cross, dot);
  const double c = std::cos(theta), s = std::sin(theta);
  TrajectoryError out;
  out.count = n;
  out.alignment = {rx - (c * ex - s * ey), ry - (s * ex + c * ey), theta};
  double sum2 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const geometry::Point2D aligned = geometry::transform_point(out.alignment, estimate[i]);
    const double d = std::hypot(aligned.x - reference[i].x, aligned.y - reference[i].y);
    sum2 += d * d;
    out.max_error_m = std::max(out.max_error_m, d);
  }
  out.ate_rmse_m = std::sqrt(sum2 * inv_n);
  return out;
}

}  // namespace mobot::slam
