#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"

namespace mobot::estimation {

// docs/algorithms.md E4: where a robot may be when nothing else is known, for global
// initialisation and the augmented-MCL injection (AMCL's free_space_indices). A cell is free
// when it was observed and its occupancy is at most `max_free_occupancy` percent (map_server's
// free_thresh 0.196 makes the images' free pixels 0).
class FreeSpaceSampler {
 public:
  static constexpr std::uint8_t kDefaultMaxFreeOccupancy = 19;

  explicit FreeSpaceSampler(const mapping::OccupancyGrid& grid,
                            std::uint8_t max_free_occupancy = kDefaultMaxFreeOccupancy);

  bool empty() const { return free_cells_.empty(); }
  std::size_t free_cell_count() const { return free_cells_.size(); }

  // A pose uniform over the free area (a free cell, then a point in it) with a uniform heading.
  // Calling it on an empty sampler is a programming error (it returns the grid origin).
  geometry::Pose2D sample(std::mt19937_64& rng) const;

 private:
  double resolution_m_;
  geometry::Pose2D origin_;
  std::vector<mapping::CellIndex> free_cells_;
};

}  // namespace mobot::estimation
