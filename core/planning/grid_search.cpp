#include "core/planning/grid_search.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <numbers>
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

std::variant<PlanError, SearchEnds> search_ends(const PlanningGrid& grid,
                                                const geometry::Pose2D& start,
                                                const geometry::Pose2D& goal,
                                                double max_escape_distance_m) {
  if (!geometry::is_finite(start) || !geometry::is_finite(goal)) return PlanError::kInvalidPose;
  if (grid.empty()) return PlanError::kNoMap;
  const auto start_cell = grid.cell_at({start.x, start.y});
  if (!start_cell) return PlanError::kStartOutsideMap;
  const auto goal_cell = grid.cell_at({goal.x, goal.y});
  if (!goal_cell) return PlanError::kGoalOutsideMap;
  if (!grid.is_traversable(*goal_cell)) return PlanError::kGoalInObstacle;
  SearchEnds ends{*start_cell, *goal_cell, {}, 0.0};
  if (grid.is_traversable(*start_cell)) return ends;
  const auto route = escape_route(grid, *start_cell, max_escape_distance_m);
  if (!route) return PlanError::kStartInObstacle;
  // The search adds the escape's last cell again as its first.
  ends.escape.assign(route->begin(), route->end() - 1);
  ends.start = route->back();
  for (std::size_t i = 1; i < route->size(); ++i) {
    const int dx = std::abs((*route)[i].x - (*route)[i - 1].x);
    const int dy = std::abs((*route)[i].y - (*route)[i - 1].y);
    ends.escape_cost_m += grid.resolution_m() * (dx + dy == 2 ? std::numbers::sqrt2 : 1.0);
  }
  return ends;
}

std::vector<geometry::Point2D> path_points(const PlanningGrid& grid,
                                           const std::vector<mapping::CellIndex>& cells,
                                           const geometry::Pose2D& start,
                                           const geometry::Pose2D& goal) {
  std::vector<geometry::Point2D> points;
  points.reserve(cells.size() + 1);
  for (const auto& cell : cells) points.push_back(grid.cell_center(cell));
  points.front() = {start.x, start.y};
  if (cells.size() == 1) {
    points.push_back({goal.x, goal.y});
  } else {
    points.back() = {goal.x, goal.y};
  }
  return points;
}

double polyline_length_m(const std::vector<geometry::Point2D>& points) {
  double length_m = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i) {
    length_m += std::hypot(points[i].x - points[i - 1].x, points[i].y - points[i - 1].y);
  }
  return length_m;
}

}  // namespace mobot::planning
