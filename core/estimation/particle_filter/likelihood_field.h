#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"

namespace mobot::estimation {

struct LikelihoodFieldOptions {
  // Distances are capped here (AMCL's laser_likelihood_max_dist, 2 m): beyond it a beam end is
  // simply "far from everything", and the cap bounds the work of preparing a map.
  double max_distance_m = 2.0;
};

// docs/algorithms.md E4: every cell's distance to the nearest occupied cell, precomputed once per
// map for the likelihood-field laser model. As AMCL's map_update_cspace: distances run between
// cell centres, only occupied cells (at or above the grid's occupied threshold) are obstacles,
// unknown cells are neither obstacles nor special (they get their distance like free ones), and
// a point off the grid is max_distance_m away.
class LikelihoodField {
 public:
  // Throws std::invalid_argument for a non-positive or non-finite max_distance_m.
  explicit LikelihoodField(const mapping::OccupancyGrid& grid,
                           const LikelihoodFieldOptions& options = {});

  int width() const { return width_; }
  int height() const { return height_; }
  double resolution_m() const { return resolution_m_; }
  const geometry::Pose2D& origin() const { return origin_; }
  double max_distance_m() const { return max_distance_m_; }
  bool has_obstacles() const { return has_obstacles_; }

  bool contains(mapping::CellIndex cell) const {
    return cell.x >= 0 && cell.y >= 0 && cell.x < width_ && cell.y < height_;
  }
  // Row-major from the bottom row, like OccupancyGrid::cells().
  const std::vector<float>& distances_m() const { return distances_m_; }
  double distance_at(mapping::CellIndex cell) const {
    return contains(cell)
               ? distances_m_[static_cast<std::size_t>(cell.y) * static_cast<std::size_t>(width_) +
                              static_cast<std::size_t>(cell.x)]
               : max_distance_m_;
  }
  // The distance of the cell holding a map-frame point (max_distance_m off the grid or NaN).
  double distance_m(geometry::Point2D point_in_map) const;
  // Whether the cell holding a map-frame point was observed and is not occupied: where the map
  // allows the robot to stand. False off the grid and for NaN.
  bool open_at(geometry::Point2D point_in_map) const;

 private:
  int width_ = 0;
  int height_ = 0;
  double resolution_m_ = 0.05;
  geometry::Pose2D origin_;
  double max_distance_m_ = 2.0;
  bool has_obstacles_ = false;
  // The row-major index of the cell holding a map-frame point; nullopt off the grid or for NaN.
  std::optional<std::size_t> index_at(geometry::Point2D point_in_map) const;

  std::vector<float> distances_m_;
  std::vector<std::uint8_t> open_;  // row-major, 1 where observed and not occupied
};

}  // namespace mobot::estimation
