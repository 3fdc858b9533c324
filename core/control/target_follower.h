#pragma once

#include <optional>

#include "core/geometry/pose2d.h"
#include "core/msgs/twist.h"

namespace mobot::control {

struct TargetFollowerOptions {
  double distance_gain = 1.2;  // 1/s on the distance error
  double bearing_gain = 1.5;   // 1/s on the bearing
  double max_linear_mps = 0.6;
  double max_angular_radps = 0.6;
  // Beyond this bearing the base turns on the spot first.
  double turn_first_rad = 0.6;
  // An alpha-beta filter on the sightings: each corrects the predicted position by alpha and the
  // velocity by beta / dt of the miss. A small beta keeps a few bad ranges (the edge of something
  // passing in front, inside the ranger's cone) from turning the velocity round.
  double alpha = 0.4;
  double beta = 0.03;
  // Without a new sighting the target is extrapolated at most this long (a pass behind a pillar);
  // after that it is held where it was last predicted.
  double max_extrapolation_s = 3.0;
  // A sighting further than this (plus the prediction's drift, 0.5 m/s times its age) from where
  // the target was predicted is taken for something else in the ranger's cone (a person passing
  // in front) and ignored, unless that many come in a row: then the target did move there.
  double gate_m = 0.12;
  int outliers_to_accept = 30;
};

// Following a moving target at a set distance (docs/algorithms.md R4, E6): the target's sightings
// (map frame) give its position and velocity through an alpha-beta filter; between them
// (occluded) it is extrapolated. The
// base closes the distance error and turns toward the bearing, with the target's own radial and
// tangential velocity as feed-forward, so a target walking away at a steady speed is followed at
// the set distance rather than at the distance a proportional law alone settles to (v / k behind).
class TargetFollower {
 public:
  explicit TargetFollower(const TargetFollowerOptions& options = {}) : options_(options) {}

  // A sighting of the target at `position` (map frame) at `stamp_s`; non-finite ones and
  // outliers (see gate_m) are ignored: false.
  bool observe(const geometry::Point2D& position, double stamp_s);
  void reset();
  bool has_target() const { return last_.has_value(); }
  // Where the target is predicted at `now_s`.
  std::optional<geometry::Point2D> predicted(double now_s) const;
  geometry::Point2D velocity() const { return velocity_; }

  // The body velocity that keeps the target `distance_m` ahead of `pose`; zero without a target.
  msgs::Twist command(const geometry::Pose2D& pose, double distance_m, double now_s) const;

 private:
  struct Sighting {
    geometry::Point2D position;
    double stamp_s = 0.0;
  };
  TargetFollowerOptions options_;
  std::optional<Sighting> last_;
  geometry::Point2D velocity_;
  int outliers_in_row_ = 0;
};

}  // namespace mobot::control
