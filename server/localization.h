#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "core/estimation/ekf_localizer.h"
#include "core/estimation/wheel_odometry.h"
#include "core/geometry/pose2d.h"
#include "core/msgs/compass_reading.h"
#include "core/msgs/landmark_bearing.h"
#include "core/msgs/laser_scan.h"
#include "core/msgs/wheel_encoders.h"
#include "core/perception/line_extractor.h"
#include "core/perception/line_segment.h"
#include "server/config.h"

namespace mobot::server {

// The robot's localization: wheel odometry (the odom frame) and the EKF of ALGORITHMS.md E2 in
// the map frame, fusing the measurement sets the config enables. With method "odometry" the EKF
// only predicts, which is dead reckoning with a growing covariance.
class Localization {
 public:
  Localization(const LocalizationSection& config, const estimation::OdometryParams& odometry,
               const geometry::Pose2D& start);

  // Re-initialises both frames at `pose` (a sim reset, the operator's initial pose).
  void reset(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance);
  // Sets the EKF pose only; odometry keeps integrating in its own frame.
  void set_pose(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance);
  // The active map's wall lines (ALGORITHMS.md E2 set 2, perception::extract_map_lines).
  void set_map_lines(std::vector<perception::LineSegment> lines) { map_lines_ = std::move(lines); }

  void on_encoders(const msgs::WheelEncoders& encoders);
  void on_compass(const msgs::CompassReading& reading);
  void on_scan(const msgs::LaserScan& scan);
  void on_bearings(const msgs::LandmarkBearings& bearings);

  const geometry::Pose2D& pose() const { return ekf_.pose(); }
  const Eigen::Matrix3d& covariance() const { return ekf_.covariance(); }
  const msgs::Odometry& odometry() const { return odometry_.odometry(); }
  double travelled_m() const { return odometry_.travelled_m(); }
  std::string method() const;
  std::string metrics_text() const;

 private:
  LocalizationSection config_;
  estimation::WheelOdometry odometry_;
  estimation::EkfLocalizer ekf_;
  perception::LineExtractor line_extractor_;
  std::vector<perception::LineSegment> map_lines_;

  std::uint64_t line_updates_ = 0;
  std::uint64_t lines_matched_ = 0;
  std::uint64_t rejected_updates_ = 0;
};

}  // namespace mobot::server
