#include "core/costmap/cost_combination.h"

#include <algorithm>
#include <cassert>

namespace mobot::costmap {

void write_max(const planning::PlanningGrid& layer, planning::PlanningGrid& master,
               const CellBounds& bounds) {
  assert(layer.width() == master.width() && layer.height() == master.height());
  const CellBounds b = bounds.clipped(master.width(), master.height());
  const std::vector<std::uint8_t>& from = layer.costs();
  std::vector<std::uint8_t>& to = master.mutable_costs();
  for (int y = b.min_y; y <= b.max_y; ++y) {
    const std::size_t row = master.index_of({0, y});
    for (int x = b.min_x; x <= b.max_x; ++x) {
      const std::size_t i = row + static_cast<std::size_t>(x);
      combine_max(from[i], to[i]);
    }
  }
}

void write_overwrite(const planning::PlanningGrid& layer, planning::PlanningGrid& master,
                     const CellBounds& bounds) {
  assert(layer.width() == master.width() && layer.height() == master.height());
  const CellBounds b = bounds.clipped(master.width(), master.height());
  for (int y = b.min_y; y <= b.max_y; ++y) {
    const std::size_t begin = master.index_of({b.min_x, y});
    const auto first = layer.costs().begin() + static_cast<std::ptrdiff_t>(begin);
    std::copy(first, first + b.width(),
              master.mutable_costs().begin() + static_cast<std::ptrdiff_t>(begin));
  }
}

}  // namespace mobot::costmap
