#include "server/stages/omni_bearing_stage.h"

#include <cmath>

#include "core/vision/bearing_match.h"

namespace mobot::server {

OmniBearingStage::OmniBearingStage(const vision::OmniCameraModel& model,
                                   std::vector<drivers::LandmarkSpot> landmarks, double range_m,
                                   double gate_rad)
    : worker_(model), landmarks_(std::move(landmarks)), range_m_(range_m), gate_rad_(gate_rad) {}

double OmniBearingStage::heading_at(double stamp_s) const {
  double heading = odometry_headings_.empty() ? 0.0 : odometry_headings_.front().second;
  for (const auto& [t_s, theta] : odometry_headings_) {
    if (t_s > stamp_s) break;
    heading = theta;
  }
  return heading;
}

void OmniBearingStage::step(TickContext& context) {
  // The odometry of the last tick (this stage runs before the estimate): its heading history
  // undoes the turn between a frame and now.
  odometry_headings_.emplace_back(context.now_s, context.odometry.pose.theta);
  while (odometry_headings_.front().first < context.now_s - 1.0) odometry_headings_.pop_front();
  if (context.image) worker_.submit(std::make_shared<const msgs::Image>(*context.image));
  const std::optional<OmniDetection> detection = worker_.take_result();
  if (!detection) return;
  const double turned_rad =
      geometry::wrap_angle(context.odometry.pose.theta - heading_at(detection->stamp_s));
  std::vector<double> detected;
  for (const vision::LandmarkBearing& seen : detection->landmarks) {
    detected.push_back(geometry::wrap_angle(seen.bearing_rad - turned_rad));
  }
  std::vector<double> predicted;
  std::vector<const drivers::LandmarkSpot*> candidates;
  for (const drivers::LandmarkSpot& landmark : landmarks_) {
    const double dx = landmark.position.x - context.pose.x;
    const double dy = landmark.position.y - context.pose.y;
    if (std::hypot(dx, dy) > range_m_) continue;
    predicted.push_back(geometry::wrap_angle(std::atan2(dy, dx) - context.pose.theta));
    candidates.push_back(&landmark);
  }
  msgs::LandmarkBearings bearings;
  bearings.stamp_s = context.now_s;
  for (const vision::BearingMatch& match : vision::match_bearings(detected, predicted, gate_rad_)) {
    const drivers::LandmarkSpot& landmark = *candidates[match.predicted_index];
    bearings.bearings.push_back(
        {landmark.name, landmark.position, detected[match.detected_index], std::nullopt});
  }
  if (!bearings.bearings.empty()) context.bearings = std::move(bearings);
}

}  // namespace mobot::server
