#include "core/estimation/particle_filter/free_space_sampler.h"

#include <numbers>

namespace mobot::estimation {

FreeSpaceSampler::FreeSpaceSampler(const mapping::OccupancyGrid& grid,
                                   std::uint8_t max_free_occupancy)
    : resolution_m_(grid.resolution_m()), origin_(grid.origin()) {
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      const std::uint8_t value = grid.at({x, y});
      if (value != mapping::OccupancyGrid::kUnknown && value <= max_free_occupancy) {
        free_cells_.push_back({x, y});
      }
    }
  }
}

geometry::Pose2D FreeSpaceSampler::sample(std::mt19937_64& rng) const {
  if (free_cells_.empty()) return origin_;
  std::uniform_int_distribution<std::size_t> pick(0, free_cells_.size() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> heading(-std::numbers::pi, std::numbers::pi);
  const mapping::CellIndex cell = free_cells_[pick(rng)];
  const geometry::Point2D local{(cell.x + unit(rng)) * resolution_m_,
                                (cell.y + unit(rng)) * resolution_m_};
  const geometry::Point2D in_map = geometry::transform_point(origin_, local);
  return {in_map.x, in_map.y, geometry::wrap_angle(heading(rng) + origin_.theta)};
}

}  // namespace mobot::estimation
