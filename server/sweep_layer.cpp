#include "server/sweep_layer.h"

namespace mobot::server {

void SweepLayer::prepare_map(const ActiveMap& map) {
  std::lock_guard lock(mutex_);
  layer_.reset(*map.grid, cell_m_);
  generation_ = map.generation;
}

geometry::Point2D SweepLayer::lattice_origin() const {
  std::lock_guard lock(mutex_);
  return layer_.lattice_origin();
}

std::optional<std::shared_ptr<const mapping::OccupancyGrid>> SweepLayer::merge(
    const mapping::OccupancyGrid& observed, std::uint64_t generation) {
  std::lock_guard lock(mutex_);
  if (layer_.empty() || generation != generation_) return std::nullopt;
  layer_.apply(observed);
  return std::make_shared<const mapping::OccupancyGrid>(layer_.grid());
}

}  // namespace mobot::server
