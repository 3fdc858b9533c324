#include "core/perception/line_fitter.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace mobot::perception {

void LineFitter::add(const geometry::Point2D& point) {
  if (count_ == 0) reference_ = point;
  const double dx = point.x - reference_.x;
  const double dy = point.y - reference_.y;
  ++count_;
  sum_x_ += dx;
  sum_y_ += dy;
  sum_xx_ += dx * dx;
  sum_xy_ += dx * dy;
  sum_yy_ += dy * dy;
}

void LineFitter::clear() { *this = LineFitter(); }

LineSegment LineFitter::fit() const {
  LineSegment line;
  line.has_endpoints = false;
  line.point_count = count_;
  if (count_ == 0) return line;
  const double n = count_;
  const double mean_x = sum_x_ / n;
  const double mean_y = sum_y_ / n;
  const double s_xx = sum_xx_ / n - mean_x * mean_x;
  const double s_xy = sum_xy_ / n - mean_x * mean_y;
  const double s_yy = sum_yy_ / n - mean_y * mean_y;
  // The normal is the direction of least scatter.
  line.alpha_rad = 0.5 * std::atan2(-2.0 * s_xy, s_yy - s_xx);
  line.rho_m = (mean_x + reference_.x) * std::cos(line.alpha_rad) +
               (mean_y + reference_.y) * std::sin(line.alpha_rad);
  return normalized(line);
}

LineSegment with_covariance(LineSegment line, std::span<const geometry::Point2D> points,
                            std::span<const double> perpendicular_var_m2) {
  const std::size_t n = std::min(points.size(), perpendicular_var_m2.size());
  if (n < 3) return line;
  const double c = std::cos(line.alpha_rad);
  const double s = std::sin(line.alpha_rad);
  // Residual d = x c + y s - rho: dd/drho = -1, dd/dalpha = -x s + y c (the along-line coordinate).
  // The fit is unweighted, so its covariance is the sandwich A^-1 B A^-1 with A = sum J^T J and
  // B = sum var_i J^T J: the first-order propagation of every point's error through the fit.
  Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
  Eigen::Matrix2d spread = Eigen::Matrix2d::Zero();
  double chi2 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double along_m = -points[i].x * s + points[i].y * c;
    const double residual_m = points[i].x * c + points[i].y * s - line.rho_m;
    const Eigen::Vector2d j(-1.0, along_m);
    normal += j * j.transpose();
    spread += perpendicular_var_m2[i] * j * j.transpose();
    chi2 += residual_m * residual_m / perpendicular_var_m2[i];
  }
  if (!(normal.determinant() > 1e-12 * normal.trace() * normal.trace())) return line;
  const Eigen::Matrix2d normal_inverse = normal.inverse();
  const double inflation = std::max(1.0, chi2 / static_cast<double>(n - 2));
  const Eigen::Matrix2d covariance = normal_inverse * spread * normal_inverse * inflation;
  line.var_rho_m2 = covariance(0, 0);
  line.var_alpha_rad2 = covariance(1, 1);
  line.cov_rho_alpha_m_rad = covariance(0, 1);
  return line;
}

}  // namespace mobot::perception
