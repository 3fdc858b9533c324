#pragma once

#include <cstdint>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/planning/planning_grid.h"

namespace mobot::planning {

struct TurningRadiusFilletOptions {
  // The base's tightest turn (a tricycle's d / tan(max_steer)); 0 leaves the path as it is.
  double min_turning_radius_m = 0.0;
  // An arc may only cross cells at or below this cost (PathSmootherOptions::max_shortcut_cost).
  std::uint8_t max_cost = 70;
  double arc_step_m = 0.2;
};

// Makes a shortcut polyline drivable by a car-like base: each corner becomes a circular arc
// tangent to both legs. The radius is the minimum turning radius where the legs are long enough
// (each leg is shared by two corners, so a corner may use half of it), smaller where they are not
// (the tracker then meets the steering stop there and cuts a little wider). An arc whose cells
// are not clear leaves its corner sharp. The first and last points are kept.
std::vector<geometry::Point2D> fillet_corners(const PlanningGrid& grid,
                                              const std::vector<geometry::Point2D>& points,
                                              const TurningRadiusFilletOptions& options);

}  // namespace mobot::planning
