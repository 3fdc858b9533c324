#include "core/estimation/line_measurement_model.h"

#include <cmath>
#include <numbers>

namespace mobot::estimation {

LineMeasurementPrediction predict_line_measurement(const geometry::Pose2D& pose,
                                                   const perception::LineSegment& map_line) {
  const double c = std::cos(map_line.alpha_rad);
  const double s = std::sin(map_line.alpha_rad);
  const double offset_m = map_line.rho_m - pose.x * c - pose.y * s;
  const double sign = offset_m < 0.0 ? -1.0 : 1.0;
  LineMeasurementPrediction out;
  out.z(0) = sign * offset_m;
  out.z(1) = geometry::wrap_angle(map_line.alpha_rad - pose.theta +
                                  (offset_m < 0.0 ? std::numbers::pi : 0.0));
  out.h << -sign * c, -sign * s, 0.0, 0.0, 0.0, -1.0;
  return out;
}

LineMeasurementPrediction predict_line_measurement(const geometry::Pose2D& pose,
                                                   const perception::LineSegment& map_line,
                                                   double observed_alpha_rad) {
  LineMeasurementPrediction out = predict_line_measurement(pose, map_line);
  if (std::abs(geometry::wrap_angle(observed_alpha_rad - out.z(1))) > std::numbers::pi / 2.0) {
    out.z(0) = -out.z(0);
    out.z(1) = geometry::wrap_angle(out.z(1) + std::numbers::pi);
    out.h.row(0) = -out.h.row(0);
  }
  return out;
}

Eigen::Vector2d line_innovation(const perception::LineSegment& observed,
                                const LineMeasurementPrediction& prediction) {
  return {observed.rho_m - prediction.z(0),
          geometry::wrap_angle(observed.alpha_rad - prediction.z(1))};
}

}  // namespace mobot::estimation
