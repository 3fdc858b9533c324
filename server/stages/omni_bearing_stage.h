#pragma once

#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "core/geometry/pose2d.h"
#include "drivers/camera_info.h"
#include "server/omni_bearing_worker.h"
#include "server/stage.h"

namespace mobot::server {

// E2's measurement 3 from the omni camera's pixels: every frame goes to the detector thread; the
// bearings it finds are matched to the known landmarks by their predicted bearings from the pose
// estimate (nearest first, within gate_rad) and handed to the estimator as this tick's landmark
// bearings. A frame shows the moment it was taken: the base's turn since then (from odometry) is
// taken off each bearing so it is the bearing now.
class OmniBearingStage final : public Stage {
 public:
  OmniBearingStage(const vision::OmniCameraModel& model, std::vector<drivers::LandmarkSpot> landmarks,
                   double range_m, double gate_rad = 0.1);

  std::string_view name() const override { return "omni_bearings"; }
  void step(TickContext& context) override;

 private:
  double heading_at(double stamp_s) const;

  OmniBearingWorker worker_;
  std::vector<drivers::LandmarkSpot> landmarks_;
  double range_m_;
  double gate_rad_;
  std::deque<std::pair<double, double>> odometry_headings_;  // (stamp, odom heading)
};

}  // namespace mobot::server
