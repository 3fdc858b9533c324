#pragma once

#include <optional>

#include "core/geometry/pose2d.h"
#include "core/vision/camera_pose.h"

namespace mobot::vision {

// docs/algorithms.md R4: the camera robot's 2-DOF head. Pan (theta1) turns about the base's
// vertical axis, tilt (theta2) about the pan link's horizontal axis; in Denavit-Hartenberg terms
// link 1 is (theta1, 90 deg, 0, l1) and link 2 (theta2, 0, l2, 0), on a column l0 high. The
// lengths are (chosen): the source gives the chain, not the numbers.
struct PanTiltHeadOptions {
  double l0_m = 0.30;  // base origin up to the pan joint
  double l1_m = 0.10;  // pan joint up to the tilt axis
  double l2_m = 0.05;  // tilt axis out to the lens
  // Where the pan axis stands on the base: forward of the base origin.
  double mount_x_m = 0.0;
  // Pan is a joint angle, not a heading: the cable stop sits behind, so a target past a limit is
  // clamped there rather than reached the other way round.
  double min_pan_rad = -2.9670597283903604;    // -170 deg
  double max_pan_rad = 2.9670597283903604;     // +170 deg
  double min_tilt_rad = -0.52359877559829882;  // -30 deg
  double max_tilt_rad = 0.78539816339744828;   // +45 deg
  double max_pan_rate_rad_s = 2.0;
  double max_tilt_rate_rad_s = 1.5;
};

// Joint angles: pan CCW from the base's heading, tilt up from the horizontal.
struct PanTilt {
  double pan_rad = 0.0;
  double tilt_rad = 0.0;

  bool operator==(const PanTilt&) const = default;
};

struct LensPosition {
  double x_m = 0.0;
  double y_m = 0.0;
  double z_m = 0.0;
};

class PanTiltHead {
 public:
  // Throws std::invalid_argument on negative or non-finite lengths, min > max limits or
  // non-positive rates.
  explicit PanTiltHead(PanTiltHeadOptions options = {});

  const PanTiltHeadOptions& options() const { return options_; }

  // R4's forward kinematics (plus the mount offset), in the base frame.
  LensPosition lens_in_base(PanTilt joints) const;
  // The joints as given (not clamped): they are what the encoders say the head is at.
  CameraPose camera_pose(const geometry::Pose2D& base_in_map, PanTilt joints) const;
  // NaN joints become 0 so a command can never carry them to the motors.
  PanTilt clamp(PanTilt joints) const;
  // One control step from `current` toward the clamped `target`, each axis at most its rate times
  // dt_s. A non-finite or non-positive dt_s does not move.
  PanTilt step_towards(PanTilt current, PanTilt target, double dt_s) const;
  // The clamped joints that put pixel (u, v) of the image seen at `current` on the optical axis.
  // The lens's offset from the joint axes (l2) is neglected: exact for a target far beyond l2.
  PanTilt centring_target(PanTilt current, double u_px, double v_px,
                          const PinholeCamera& camera) const;
  // Where a target seen at pixel (u, v) and `range_m` along that pixel's ray from the lens (the
  // ultrasonic range toward it) stands in the base frame. nullopt for non-finite input or a
  // non-positive range.
  std::optional<geometry::Point2D> target_in_base(PanTilt joints, double u_px, double v_px,
                                                  double range_m,
                                                  const PinholeCamera& camera) const;

 private:
  PanTiltHeadOptions options_;
};

// Pixel coordinates put the principal point at (width/2, height/2), as R4's Px/2 does.
//
// R4's bearing: a0 = -(j - Px/2) / Px * rx, linear in the column. It is exact at the centre and
// at the image edges but off in between (up to 0.0195 rad at 60 deg FOV, 55 % of the way from the
// centre to an edge), because a pinhole maps angle to column through a tangent.
double bearing_from_column_linear_rad(double column_px, const PinholeCamera& camera);
// The pinhole's bearing, atan(-(j - Px/2) / f): what the tracking loop uses to turn the head.
double bearing_from_column_rad(double column_px, const PinholeCamera& camera);
// The pinhole's elevation of a row on the centre column, up positive.
double elevation_from_row_rad(double row_px, const PinholeCamera& camera);

}  // namespace mobot::vision
