#pragma once

namespace mobot::vision {

// Where a camera's optical centre is and where it looks, in the map frame: yaw CCW from the map's
// x axis, pitch up from the horizontal (a pan/tilt head has no roll).
struct CameraPose {
  double x_m = 0.0;
  double y_m = 0.0;
  double z_m = 0.0;
  double yaw_rad = 0.0;
  double pitch_rad = 0.0;
};

// A perspective (pinhole) camera without distortion: the principal point is the image centre and
// pixels are square, so the horizontal field of view fixes the focal length.
struct PinholeCamera {
  int width_px = 640;
  int height_px = 480;
  double horizontal_fov_rad = 1.0471975511965976;  // 60 deg

  double focal_px() const;
};

}  // namespace mobot::vision
