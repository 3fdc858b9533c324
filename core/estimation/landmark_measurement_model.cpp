#include "core/estimation/landmark_measurement_model.h"

#include <cmath>

namespace mobot::estimation {
namespace {

// Below this the direction to the landmark is numerically meaningless.
constexpr double kMinDistanceM = 1e-6;

}  // namespace

std::optional<ScalarMeasurementPrediction> predict_bearing(const geometry::Pose2D& pose,
                                                           const geometry::Point2D& landmark) {
  const double dx = landmark.x - pose.x;
  const double dy = landmark.y - pose.y;
  const double d2 = dx * dx + dy * dy;
  if (!(d2 > kMinDistanceM * kMinDistanceM)) return std::nullopt;
  ScalarMeasurementPrediction out;
  out.z = geometry::wrap_angle(std::atan2(dy, dx) - pose.theta);
  out.h << dy / d2, -dx / d2, -1.0;
  return out;
}

std::optional<ScalarMeasurementPrediction> predict_range(const geometry::Pose2D& pose,
                                                         const geometry::Point2D& landmark) {
  const double dx = pose.x - landmark.x;
  const double dy = pose.y - landmark.y;
  const double range_m = std::hypot(dx, dy);
  if (!(range_m > kMinDistanceM)) return std::nullopt;
  ScalarMeasurementPrediction out;
  out.z = range_m;
  out.h << dx / range_m, dy / range_m, 0.0;
  return out;
}

}  // namespace mobot::estimation
