#pragma once

#include <cstdint>
#include <vector>

#include "core/mapping/occupancy_grid.h"
#include "core/perception/line_segment.h"

namespace mobot::perception {

struct MapLineExtractorOptions {
  // A cell is a wall at or above this occupancy and free at or below free_max_value
  // (map_saver's thresholds); unknown cells are neither.
  std::uint8_t occupied_min_value = mapping::OccupancyGrid::kOccupiedThreshold;
  std::uint8_t free_max_value = 25;
  // Split-and-merge tolerance on the wall outline, in cells: a 45 deg wall is a staircase whose
  // cell centres stray up to ~0.7 cells from the true line.
  double split_tolerance_cells = 1.0;
  double min_length_m = 0.3;
  // Keep only faces that look onto free space: the only ones a laser on the robot can see.
  bool require_free_side = true;
  double min_free_fraction = 0.5;
};

// Extracts the wall faces of an occupancy grid as line segments in the map frame: the outline of
// every blob of occupied cells (OpenCV border following) is cut into straight pieces by
// split-and-merge, each piece is refitted by total least squares, and the line is moved half a
// cell from the cell centres to the face between the wall and its free side, where laser returns
// come from. A one-cell-thick wall with free space on both sides yields both of its faces.
// Covariances assume uniform quantisation error (resolution^2 / 12) per outline cell.
// Deterministic; about a millisecond for a 400 x 300 grid.
std::vector<LineSegment> extract_map_lines(const mapping::OccupancyGrid& grid,
                                           const MapLineExtractorOptions& options = {});

}  // namespace mobot::perception
