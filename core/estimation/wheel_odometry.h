#pragma once

#include <deque>

#include "core/msgs/odometry.h"
#include "core/msgs/wheel_encoders.h"

namespace mobot::estimation {

// Geometry that turns encoder ticks into wheel travel. Left and right radii are separate because
// calibration (UMBmark) corrects them separately.
struct OdometryParams {
  double left_wheel_radius_m = 0.1;
  double right_wheel_radius_m = 0.1;
  double track_m = 0.6;
  int ticks_per_wheel_rev = 10000;
  // The velocity is the encoders' travel over at least this long. Over one 20 ms control period
  // a Dashgo wheel (1200 ticks per turn of a 0.128 m wheel) moves a whole tick only above
  // 0.017 m/s, so a per-period velocity reads 0 or 0.017 m/s while the base turns slowly on the
  // spot, and a planner that accelerates from the measured velocity (DWA) never gets going.
  double velocity_window_s = 0.1;
};

// How far each wheel rolled in the last update.
struct WheelTravel {
  double left_m = 0.0;
  double right_m = 0.0;
};

// Dead reckoning from cumulative encoder counts (docs/algorithms.md E1), in the odom frame.
class WheelOdometry {
 public:
  explicit WheelOdometry(const OdometryParams& params, geometry::Pose2D start = {});

  // The first reading only anchors the counters; later ones advance the pose. The twist is the
  // travel since the newest reading at least velocity_window_s old (or the oldest there is).
  const msgs::Odometry& update(const msgs::WheelEncoders& encoders);
  const msgs::Odometry& odometry() const { return odometry_; }
  // Distance rolled by the base centre since construction (for run statistics).
  double travelled_m() const { return travelled_m_; }
  const WheelTravel& last_travel() const { return last_travel_; }
  const OdometryParams& params() const { return params_; }
  void reset(geometry::Pose2D pose);

 private:
  OdometryParams params_;
  // The wheels' travel between two readings.
  WheelTravel travel(const msgs::WheelEncoders& from, const msgs::WheelEncoders& to) const;

  // The readings of the last velocity_window_s and the one before them, oldest first; the newest
  // is the last reading (empty before the first).
  std::deque<msgs::WheelEncoders> recent_;
  msgs::Odometry odometry_;
  double travelled_m_ = 0.0;
  WheelTravel last_travel_;
};

}  // namespace mobot::estimation
