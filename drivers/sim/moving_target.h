#pragma once

#include <cstdint>
#include <vector>

#include "core/geometry/pose2d.h"

namespace mobot::sim {

struct RgbColor {
  std::uint8_t r = 0;
  std::uint8_t g = 0;
  std::uint8_t b = 0;

  bool operator==(const RgbColor&) const = default;
};

// What a world file or a request asks for; MovingTarget checks it.
struct MovingTargetSpec {
  RgbColor color{220, 30, 30};
  double radius_m = 0.1;
  double height_m = 0.5;                // of the ball's centre above the floor
  std::vector<geometry::Point2D> path;  // map frame, at least one point
  double speed_mps = 0.3;
  // true: from the last point straight back to the first and round again; false: stop at the end.
  bool loop = true;
};

// A coloured ball carried at constant speed along a polyline, for the cameras to see and a tracker
// (E6) to follow. It is scenery, not a body: it goes wherever its path says, through walls too,
// and nothing collides with it.
class MovingTarget {
 public:
  // Throws std::invalid_argument naming the field: a non-finite number, radius_m <= 0,
  // height_m < 0, speed_mps < 0 or an empty path.
  explicit MovingTarget(MovingTargetSpec spec);

  // Where the ball's centre is (map x, y) time_s after it was added; before that (time_s < 0) it
  // waits at the first point. Throws std::invalid_argument for a non-finite time.
  geometry::Point2D position_at(double time_s) const;

  const MovingTargetSpec& spec() const { return spec_; }
  // One lap: through every point, and back to the first when it loops.
  double path_length_m() const { return cumulative_m_.back(); }

 private:
  geometry::Point2D point_at_distance(double distance_m) const;
  const geometry::Point2D& vertex(std::size_t i) const;

  MovingTargetSpec spec_;
  // Distance along the path to each vertex; when looping the last entry is the first point again.
  std::vector<double> cumulative_m_;
};

}  // namespace mobot::sim
