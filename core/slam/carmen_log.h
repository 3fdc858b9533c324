#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/msgs/laser_scan.h"

namespace mobot::slam {

// One laser message of a CARMEN log (the Radish data sets: Intel, MIT CSAIL, Freiburg, ACES, ...).
// FLASER n r_1..r_n x y theta odom_x odom_y odom_theta ipc_timestamp host logger_timestamp: n
// beams over 180 deg from -90 deg; x y theta is the laser pose (corrected logs: the reference),
// odom_* the robot's odometry. ROBOTLASER1 carries its own start angle, field of view and maximum
// range, the laser pose and the robot's odometry pose.
struct CarmenLaser {
  double timestamp_s = 0.0;
  float angle_min_rad = 0.0F;
  float angle_increment_rad = 0.0F;
  // Readings at or above this are "no return". FLASER does not say; 0 means "not given".
  float range_max_m = 0.0F;
  std::vector<float> ranges_m;
  geometry::Pose2D laser_pose;  // in the log's map/odometry frame as the log gives it
  geometry::Pose2D odom_pose;   // of the robot base
};

struct CarmenLine {
  enum class Kind {
    kLaser,      // `laser` holds the record
    kSkipped,    // empty, a comment, or a message type this reader does not use
    kMalformed,  // a laser line that does not parse; `error` says why
  };
  Kind kind = Kind::kSkipped;
  std::optional<CarmenLaser> laser;
  std::string error;
};

// Parses one line of a CARMEN log. Never throws on bad input: a FLASER / ROBOTLASER1 line with a
// wrong field count, a non-number, a non-finite pose or a beam count outside 1..10000 is
// kMalformed.
CarmenLine parse_carmen_line(std::string_view line);

// The beam geometry of an n-beam FLASER sweep over 180 deg: 181 or 361 beams (an odd count) reach
// both +-90 deg; 180 or 360 beams start at -90 deg and stop one step short of +90.
double flaser_angle_increment_rad(std::size_t beam_count);

// A LaserScan from a record. The laser pose relative to the base is `sensor_in_base` (FLASER
// logs: identity, the logged poses are the laser's). Readings at or above `no_return_range_m`
// (or the record's own range_max when it gives one) mean no return.
msgs::LaserScan to_laser_scan(const CarmenLaser& laser, double no_return_range_m,
                              const geometry::Pose2D& sensor_in_base = {});

}  // namespace mobot::slam
