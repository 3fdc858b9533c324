#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/mapping/occupancy_grid.h"
#include "core/planning/planning_grid.h"

namespace mobot::planning {

struct VoronoiRoadmapOptions {
  // Two obstacle cells ("sites") closer together than this never make a roadmap cell between them:
  // the gap between them is narrower than the robot, so their bisector is the middle of no passage
  // it can use. Without this, Lau's criterion alone (sites not 8-adjacent) grows a hair of roadmap
  // every couple of cells along a rasterised sloped wall, whose protruding cells are two apart, and
  // two long hairs from every one-cell bump of a scanned wall. Measured between site centres. The
  // default is R1's footprint width, twice PlanningGridOptions::inscribed_radius_m; 0 gives the
  // plain criterion of Lau et al.
  double min_passage_width_m = 0.6;
};

// docs/algorithms.md C1: the roadmap of the Voronoi planner, a generalized Voronoi diagram (GVD) of
// a planning grid, about one cell wide, kept where the robot fits.
//
// Sites are the obstacle cells: lethal and unknown (the planner never enters either). An exact
// Euclidean distance transform (Meijster, Roerdink, Hesselink 2000) gives every cell its nearest
// site. A cell is on the diagram, as in DynamicVoronoi (Lau, Sprunk, Burgard, "Improved updating of
// Euclidean distance maps and Voronoi diagrams", IROS 2010), when a 4-neighbour's site is neither
// its own nor 8-adjacent to it, so the two cells lie on either side of the bisector of two
// obstacles (or of two distant parts of one obstacle, as the two walls of a room, which a GVD of
// connected obstacles would miss). Of each such pair only the cell nearer the bisector is marked
// (the one whose own site is the nearer relative to the other's; on a tie the lower flat index),
// which keeps the diagram about one cell wide. Finally only traversable cells (cost < kInscribed)
// are kept: exactly those whose clearance exceeds the robot's inscribed radius when the grid came
// from PlanningGridBuilder, i.e. the mid-points of free passages wider than the robot.
//
// The grid's border is not an obstacle, as in PlanningGridBuilder's distances: a map whose free
// space reaches the border has no wall there.
class VoronoiRoadmap {
 public:
  static constexpr std::uint32_t kNoSite = 0xFFFFFFFFU;

  // An empty roadmap (no cells).
  VoronoiRoadmap() = default;
  // Throws std::invalid_argument on a negative or non-finite option.
  explicit VoronoiRoadmap(const PlanningGrid& grid, const VoronoiRoadmapOptions& options = {});

  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return mask_.empty(); }
  // One byte per grid cell, row-major like PlanningGrid::costs(): 1 on the roadmap, else 0 (for
  // the planner's step costs and a dashboard overlay).
  const std::vector<std::uint8_t>& mask() const { return mask_; }
  bool contains(mapping::CellIndex cell) const {
    return cell.x >= 0 && cell.y >= 0 && cell.x < width_ && cell.y < height_;
  }
  bool on_roadmap(mapping::CellIndex cell) const {
    return contains(cell) && mask_[index_of(cell)] != 0;
  }
  // The number of roadmap cells.
  std::size_t size() const { return size_; }

  // The nearest obstacle cell (an obstacle cell is its own site), or nullopt when the grid has no
  // obstacle or the cell lies outside it. Ties between equally near sites are broken
  // deterministically.
  std::optional<mapping::CellIndex> site_of(mapping::CellIndex cell) const;
  // Distance from the cell's centre to its site's centre; infinity when site_of has none.
  double clearance_cells(mapping::CellIndex cell) const;
  double clearance_m(mapping::CellIndex cell) const {
    return clearance_cells(cell) * resolution_m_;
  }

 private:
  std::size_t index_of(mapping::CellIndex cell) const {
    return static_cast<std::size_t>(cell.y) * static_cast<std::size_t>(width_) +
           static_cast<std::size_t>(cell.x);
  }
  // Fills sites_ with each cell's nearest obstacle cell (flat index) or kNoSite.
  void compute_sites(const PlanningGrid& grid);
  // Marks the cell of the pair (a, b) of 4-neighbours that lies nearer their sites' bisector, if
  // the pair straddles one.
  void mark_pair(const PlanningGrid& grid, std::size_t a, std::size_t b,
                 double min_separation_squared_cells);

  int width_ = 0;
  int height_ = 0;
  double resolution_m_ = 0.05;
  std::vector<std::uint32_t> sites_;
  std::vector<std::uint8_t> mask_;
  std::size_t size_ = 0;
};

}  // namespace mobot::planning
