#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/geometry/pose2d.h"

#include "core/vision/camera_pose.h"
#include "core/vision/omni_camera_model.h"

namespace mobot::drivers {

// A landmark the omni camera looks for, at its known place in the map (E2's lit cylinders).
struct LandmarkSpot {
  std::string name;
  geometry::Point2D position;
};

// What a robot's camera is, for the API and for whoever reads its pixels: "pan_tilt" (a pinhole
// camera on the PanTiltDriver's head), "omni" (R1's mirror camera) or "fixed" (a pinhole camera
// looking ahead from the base).
struct CameraInfo {
  std::string kind = "fixed";
  vision::PinholeCamera pinhole;           // pan_tilt and fixed
  std::optional<vision::OmniCameraModel> omni;  // omni
  double rate_hz = 10.0;
  // The lens above the floor (omni: the mirror's single viewpoint).
  double height_m = 0.0;
  // The ranger beside the lens (R4) sees the target only while it is within this cone of the
  // optical axis; 0 without one.
  double range_cone_rad = 0.0;
  // The omni camera's landmarks and how far away it can make one out.
  std::vector<LandmarkSpot> landmarks;
  double landmark_range_m = 0.0;
};

}  // namespace mobot::drivers
