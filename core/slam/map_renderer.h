#pragma once

#include <span>

#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"
#include "core/slam/scan_points.h"

namespace mobot::slam {

struct MapRenderOptions {
  // E5: the Dashgo thesis's gmapping map has 0.05 m cells.
  double resolution_m = 0.05;
  // The origin is a multiple of this in x and y, so two renders of a growing map share their cell
  // boundaries and a caller can diff them in fixed tiles (64 cells of 0.05 m = 3.2 m). 0: no
  // alignment (the origin is the lower-left corner of the points' bounding box).
  double align_m = 3.2;
  // Empty border around the observed area, so walls at the edge keep a free/unknown rim.
  double margin_m = 0.5;
  // Karto's / slam_toolbox's occupancy rule: a cell is occupied (100) when at least this fraction
  // of the rays that reached it ended in it, free (0) otherwise. Counting beats log-odds for a
  // one-shot render: a wall cell grazed by the neighbouring beams of the same scan stays a wall.
  double occupied_hit_ratio = 0.1;
  // Cells reached by fewer rays than this stay unknown (255).
  int min_visits = 1;
  // Beams beyond this range mark free space up to it but no hit (gmapping's maxUrange 8 m).
  double max_range_m = 8.0;
};

// One scan as a renderer sees it: the base pose in the map frame and the scan's points in the base
// frame (with the sensor's origin, so rays start at the sensor).
struct PosedScan {
  geometry::Pose2D base_in_map;
  const ScanPoints* points = nullptr;
};

// Ray casts every scan into an occupancy grid (ROS semantics: 0..100, 255 never observed).
// Throws std::invalid_argument on a non-positive resolution or negative align/margin.
mapping::OccupancyGrid render_occupancy_grid(std::span<const PosedScan> scans,
                                             const MapRenderOptions& options = {});

}  // namespace mobot::slam
