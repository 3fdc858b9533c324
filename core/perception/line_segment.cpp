#include "core/perception/line_segment.h"

#include <cmath>
#include <numbers>

namespace mobot::perception {

double LineSegment::length_m() const {
  if (!has_endpoints) return 0.0;
  return std::hypot(end.x - start.x, end.y - start.y);
}

bool is_valid(const LineSegment& line) {
  const bool params_finite = std::isfinite(line.rho_m) && std::isfinite(line.alpha_rad) &&
                             std::isfinite(line.var_rho_m2) && std::isfinite(line.var_alpha_rad2) &&
                             std::isfinite(line.cov_rho_alpha_m_rad);
  const bool ends_finite =
      !line.has_endpoints || (std::isfinite(line.start.x) && std::isfinite(line.start.y) &&
                              std::isfinite(line.end.x) && std::isfinite(line.end.y));
  return params_finite && ends_finite && line.rho_m >= 0.0 && line.var_rho_m2 >= 0.0 &&
         line.var_alpha_rad2 >= 0.0;
}

LineSegment normalized(LineSegment line) {
  if (line.rho_m < 0.0) {
    line.rho_m = -line.rho_m;
    line.alpha_rad += std::numbers::pi;
    line.cov_rho_alpha_m_rad = -line.cov_rho_alpha_m_rad;
    line.free_side = -line.free_side;
  }
  line.alpha_rad = geometry::wrap_angle(line.alpha_rad);
  return line;
}

LineSegment transform_line(const geometry::Pose2D& frame, const LineSegment& line) {
  LineSegment out = line;
  out.alpha_rad = line.alpha_rad + frame.theta;
  const double c = std::cos(out.alpha_rad);
  const double s = std::sin(out.alpha_rad);
  // The normal rotates with the frame; the origin shift adds its projection on the new normal.
  out.rho_m = line.rho_m + frame.x * c + frame.y * s;
  // d rho' / d alpha = -x sin + y cos; d alpha' / d alpha = 1.
  const double drho_dalpha = -frame.x * s + frame.y * c;
  out.var_rho_m2 = line.var_rho_m2 + 2.0 * drho_dalpha * line.cov_rho_alpha_m_rad +
                   drho_dalpha * drho_dalpha * line.var_alpha_rad2;
  out.cov_rho_alpha_m_rad = line.cov_rho_alpha_m_rad + drho_dalpha * line.var_alpha_rad2;
  if (line.has_endpoints) {
    out.start = geometry::transform_point(frame, line.start);
    out.end = geometry::transform_point(frame, line.end);
  }
  return normalized(out);
}

double signed_distance(const LineSegment& line, const geometry::Point2D& point) {
  return point.x * std::cos(line.alpha_rad) + point.y * std::sin(line.alpha_rad) - line.rho_m;
}

geometry::Point2D project_onto(const LineSegment& line, const geometry::Point2D& point) {
  const double d = signed_distance(line, point);
  return {point.x - d * std::cos(line.alpha_rad), point.y - d * std::sin(line.alpha_rad)};
}

}  // namespace mobot::perception
