#include "core/planning/start_escape.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

#include "core/planning/grid_steps.h"

namespace mobot::planning {

std::optional<std::vector<mapping::CellIndex>> escape_route(const PlanningGrid& grid,
                                                            mapping::CellIndex start,
                                                            double max_distance_m) {
  const double limit_cells = max_distance_m / grid.resolution_m();
  const int radius = static_cast<int>(
      std::min(std::ceil(limit_cells), static_cast<double>(std::max(grid.width(), grid.height()))));
  const int side = 2 * radius + 1;
  const auto local_index = [&](mapping::CellIndex c) {
    return static_cast<std::size_t>(c.y - start.y + radius) * static_cast<std::size_t>(side) +
           static_cast<std::size_t>(c.x - start.x + radius);
  };
  const bool start_lethal = grid.cost(start) == PlanningGrid::kLethal;
  const auto enterable = [&](mapping::CellIndex c) {
    const std::uint8_t cost = grid.cost(c);
    return PlanningGrid::is_traversable_cost(cost) || cost == PlanningGrid::kInscribed ||
           cost == PlanningGrid::kUnknown || (start_lethal && cost == PlanningGrid::kLethal);
  };

  const auto window_cells = static_cast<std::size_t>(side) * static_cast<std::size_t>(side);
  std::vector<double> dist(window_cells, std::numeric_limits<double>::infinity());
  std::vector<mapping::CellIndex> parent(window_cells, start);
  using Item = std::pair<double, std::size_t>;  // distance, local index: a deterministic order
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  const auto cell_of_local = [&](std::size_t li) {
    const auto s = static_cast<std::size_t>(side);
    return mapping::CellIndex{static_cast<int>(li % s) + start.x - radius,
                              static_cast<int>(li / s) + start.y - radius};
  };
  dist[local_index(start)] = 0.0;
  open.push({0.0, local_index(start)});
  while (!open.empty()) {
    const auto [d, li] = open.top();
    open.pop();
    if (d > dist[li]) continue;
    const mapping::CellIndex cell = cell_of_local(li);
    if (grid.is_traversable(cell)) {
      std::vector<mapping::CellIndex> route{cell};
      while (!(route.back() == start)) route.push_back(parent[local_index(route.back())]);
      std::reverse(route.begin(), route.end());
      return route;
    }
    for (const GridStep& step : kGridSteps) {
      const mapping::CellIndex next{cell.x + step.dx, cell.y + step.dy};
      if (!grid.contains(next) || std::abs(next.x - start.x) > radius ||
          std::abs(next.y - start.y) > radius || !enterable(next)) {
        continue;
      }
      const double nd = d + step.length_cells;
      const std::size_t ln = local_index(next);
      if (nd > limit_cells || nd >= dist[ln]) continue;
      dist[ln] = nd;
      parent[ln] = cell;
      open.push({nd, ln});
    }
  }
  return std::nullopt;
}

}  // namespace mobot::planning
