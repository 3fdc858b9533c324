#pragma once

#include <cstddef>
#include <vector>

#include "core/geometry/pose2d.h"

namespace mobot::planning {

// A map-frame polyline the robot follows, indexed by arc length s in metres from its first point.
// Consecutive duplicate points are dropped, so every segment has a positive length.
class Path {
 public:
  Path() = default;
  explicit Path(std::vector<geometry::Point2D> points_in_map);

  const std::vector<geometry::Point2D>& points() const { return points_; }
  bool empty() const { return points_.empty(); }
  std::size_t size() const { return points_.size(); }
  bool all_finite() const;
  double length_m() const { return cumulative_m_.empty() ? 0.0 : cumulative_m_.back(); }
  // Arc length at vertex i.
  double s_at_vertex(std::size_t i) const { return cumulative_m_[i]; }
  const geometry::Point2D& front() const { return points_.front(); }
  const geometry::Point2D& back() const { return points_.back(); }

  // The point at arc length s (clamped to the path). The path must not be empty.
  geometry::Point2D point_at(double s_m) const;
  // Direction of travel at arc length s: the segment holding s, at a vertex the segment leaving
  // it, at the end the last segment. 0 for a single-point path.
  double heading_at(double s_m) const;
  // Arc length of the path point nearest to `point` among those with s in
  // [from_s_m, from_s_m + window_m]; the window keeps a path that doubles back on itself from
  // snapping the robot's progress to the wrong leg.
  double project(geometry::Point2D point, double from_s_m, double window_m) const;

 private:
  std::size_t segment_at(double s_m) const;

  std::vector<geometry::Point2D> points_;
  std::vector<double> cumulative_m_;
};

double distance(geometry::Point2D a, geometry::Point2D b);

}  // namespace mobot::planning
