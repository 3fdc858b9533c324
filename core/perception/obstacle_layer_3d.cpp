#include "core/perception/obstacle_layer_3d.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace mobot::perception {

void ObstacleLayer3D::reset(const mapping::OccupancyGrid& map, double cell_m) {
  if (map.cells().empty()) throw std::invalid_argument("the 3D layer needs a map");
  if (!(cell_m > 0.0) || !std::isfinite(cell_m)) {
    throw std::invalid_argument("the 3D layer's cell must be positive");
  }
  // The layer is axis-aligned; a rotated map is covered by its bounding box.
  const geometry::Pose2D& origin = map.origin();
  const double c = std::cos(origin.theta);
  const double s = std::sin(origin.theta);
  double min_x = origin.x;
  double max_x = origin.x;
  double min_y = origin.y;
  double max_y = origin.y;
  for (const auto& [u, v] : std::array<std::pair<double, double>, 3>{
           {{map.width_m(), 0.0}, {0.0, map.height_m()}, {map.width_m(), map.height_m()}}}) {
    min_x = std::min(min_x, origin.x + c * u - s * v);
    max_x = std::max(max_x, origin.x + c * u - s * v);
    min_y = std::min(min_y, origin.y + s * u + c * v);
    max_y = std::max(max_y, origin.y + s * u + c * v);
  }
  const int width = static_cast<int>(std::ceil((max_x - min_x) / cell_m));
  const int height = static_cast<int>(std::ceil((max_y - min_y) / cell_m));
  grid_ = mapping::OccupancyGrid(width, height, cell_m, {min_x, min_y, 0.0},
                                 mapping::OccupancyGrid::kUnknown);
}

int ObstacleLayer3D::apply(const mapping::OccupancyGrid& observed) {
  if (empty()) return 0;
  const double cell_m = grid_.resolution_m();
  // Whole-cell offset of the observed grid on the layer's lattice.
  const int offset_x =
      static_cast<int>(std::lround((observed.origin().x - grid_.origin().x) / cell_m));
  const int offset_y =
      static_cast<int>(std::lround((observed.origin().y - grid_.origin().y) / cell_m));
  int copied = 0;
  for (int y = 0; y < observed.height(); ++y) {
    for (int x = 0; x < observed.width(); ++x) {
      const std::uint8_t value = observed.at({x, y});
      const mapping::CellIndex target{x + offset_x, y + offset_y};
      if (value == mapping::OccupancyGrid::kUnknown || !grid_.contains(target)) continue;
      grid_.set(target, value);
      ++copied;
    }
  }
  return copied;
}

}  // namespace mobot::perception
