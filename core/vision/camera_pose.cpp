#include "core/vision/camera_pose.h"

#include <cmath>

namespace mobot::vision {

double PinholeCamera::focal_px() const {
  return 0.5 * width_px / std::tan(0.5 * horizontal_fov_rad);
}

}  // namespace mobot::vision
