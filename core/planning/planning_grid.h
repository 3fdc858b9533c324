#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"

namespace mobot::planning {

// A costmap-like grid the planners search, with ROS costmap_2d cost values: 0 free, 1..252 the
// inflation band (higher = closer to an obstacle), 253 inscribed (the robot's centre here means its
// body touches an obstacle), 254 lethal (the obstacle itself), 255 unknown.
// Same geometry conventions as mapping::OccupancyGrid: the origin is the pose of the lower-left
// corner of cell (0, 0), row y grows with the map frame's y. A default-constructed grid is empty.
class PlanningGrid {
 public:
  static constexpr std::uint8_t kFree = 0;
  static constexpr std::uint8_t kMaxInflated = 252;
  static constexpr std::uint8_t kInscribed = 253;
  static constexpr std::uint8_t kLethal = 254;
  static constexpr std::uint8_t kUnknown = 255;

  PlanningGrid() = default;
  // Throws std::invalid_argument on non-positive sizes or a non-positive resolution.
  PlanningGrid(int width_cells, int height_cells, double resolution_m, geometry::Pose2D origin,
               std::uint8_t fill = kFree);

  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return costs_.empty(); }
  double resolution_m() const { return resolution_m_; }
  const geometry::Pose2D& origin() const { return origin_; }
  const std::vector<std::uint8_t>& costs() const { return costs_; }
  std::vector<std::uint8_t>& mutable_costs() { return costs_; }

  bool contains(mapping::CellIndex cell) const {
    return cell.x >= 0 && cell.y >= 0 && cell.x < width_ && cell.y < height_;
  }
  std::size_t index_of(mapping::CellIndex cell) const {
    return static_cast<std::size_t>(cell.y) * static_cast<std::size_t>(width_) +
           static_cast<std::size_t>(cell.x);
  }
  mapping::CellIndex cell_of(std::size_t index) const {
    const auto w = static_cast<std::size_t>(width_);
    return {static_cast<int>(index % w), static_cast<int>(index / w)};
  }
  std::uint8_t cost(mapping::CellIndex cell) const { return costs_[index_of(cell)]; }
  void set_cost(mapping::CellIndex cell, std::uint8_t cost) { costs_[index_of(cell)] = cost; }

  // The robot's centre may occupy the cell: below the inscribed cost. Unknown cells are never
  // traversable here; the grid builder decides whether unknown space is kept as unknown.
  static bool is_traversable_cost(std::uint8_t cost) { return cost < kInscribed; }
  bool is_traversable(mapping::CellIndex cell) const {
    return contains(cell) && is_traversable_cost(cost(cell));
  }

  // The cell holding a map-frame point, or nullopt when the point lies outside the grid or is not
  // finite.
  std::optional<mapping::CellIndex> cell_at(geometry::Point2D point_in_map) const;
  geometry::Point2D cell_center(mapping::CellIndex cell) const;
  // Point in the grid's own (unrotated, origin at the corner of cell (0, 0)) frame, in cells.
  geometry::Point2D to_grid_frame_cells(geometry::Point2D point_in_map) const;

 private:
  int width_ = 0;
  int height_ = 0;
  double resolution_m_ = 0.05;
  geometry::Pose2D origin_;
  std::vector<std::uint8_t> costs_;
};

}  // namespace mobot::planning
