#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "core/geometry/pose2d.h"

namespace mobot::mapping {

struct CellIndex {
  int x = 0;  // column, grows with the map frame's x
  int y = 0;  // row, grows with the map frame's y (row 0 is the bottom of the map image)

  bool operator==(const CellIndex&) const = default;
};

// A 2D occupancy grid in the map frame with ROS OccupancyGrid semantics, stored as bytes:
// 0..100 is the occupancy probability in percent, kUnknown marks cells never observed.
// The origin is the pose of the lower-left corner of cell (0, 0).
class OccupancyGrid {
 public:
  static constexpr std::uint8_t kFree = 0;
  static constexpr std::uint8_t kOccupied = 100;
  static constexpr std::uint8_t kUnknown = 255;
  // A cell at or above this value blocks (ROS map_server's 0.65 occupied threshold).
  static constexpr std::uint8_t kOccupiedThreshold = 65;

  OccupancyGrid() = default;
  OccupancyGrid(int width_cells, int height_cells, double resolution_m, geometry::Pose2D origin,
                std::uint8_t fill = kUnknown);

  int width() const { return width_; }
  int height() const { return height_; }
  double resolution_m() const { return resolution_m_; }
  const geometry::Pose2D& origin() const { return origin_; }
  const std::vector<std::uint8_t>& cells() const { return cells_; }
  std::vector<std::uint8_t>& mutable_cells() { return cells_; }

  bool contains(CellIndex cell) const {
    return cell.x >= 0 && cell.y >= 0 && cell.x < width_ && cell.y < height_;
  }
  std::uint8_t at(CellIndex cell) const { return cells_[index_of(cell)]; }
  void set(CellIndex cell, std::uint8_t value) { cells_[index_of(cell)] = value; }
  bool is_occupied(CellIndex cell) const {
    const std::uint8_t v = at(cell);
    return v != kUnknown && v >= kOccupiedThreshold;
  }

  // The cell holding a map-frame point, or nullopt when the point lies outside the grid.
  std::optional<CellIndex> cell_at(geometry::Point2D point_in_map) const;
  // Like cell_at but without the bounds check (the index may lie outside the grid).
  CellIndex cell_at_unchecked(geometry::Point2D point_in_map) const;
  geometry::Point2D cell_center(CellIndex cell) const;

  double width_m() const { return width_ * resolution_m_; }
  double height_m() const { return height_ * resolution_m_; }

 private:
  std::size_t index_of(CellIndex cell) const {
    return static_cast<std::size_t>(cell.y) * static_cast<std::size_t>(width_) +
           static_cast<std::size_t>(cell.x);
  }

  int width_ = 0;
  int height_ = 0;
  double resolution_m_ = 0.05;
  geometry::Pose2D origin_;
  std::vector<std::uint8_t> cells_;
};

}  // namespace mobot::mapping
