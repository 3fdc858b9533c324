#include "core/planning/turning_radius_fillet.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/planning/line_of_sight.h"

namespace mobot::planning {
namespace {

struct Vector {
  double x = 0.0;
  double y = 0.0;
};

Vector unit(geometry::Point2D from, geometry::Point2D to, double& length_m) {
  length_m = std::hypot(to.x - from.x, to.y - from.y);
  return {(to.x - from.x) / length_m, (to.y - from.y) / length_m};
}

// The arc from the tangent point on the incoming leg to the one on the outgoing leg, excluding
// its ends' exact corner, in steps of at most step_m.
std::vector<geometry::Point2D> corner_arc(geometry::Point2D corner, Vector in, Vector out,
                                          double radius_m, double step_m) {
  const double turn_rad = std::atan2(in.x * out.y - in.y * out.x, in.x * out.x + in.y * out.y);
  const double tangent_m = radius_m * std::tan(std::abs(turn_rad) / 2.0);
  const geometry::Point2D entry{corner.x - in.x * tangent_m, corner.y - in.y * tangent_m};
  // The centre lies on the inside of the turn, perpendicular to the incoming leg.
  const double side = turn_rad > 0.0 ? 1.0 : -1.0;
  const geometry::Point2D centre{entry.x - side * in.y * radius_m, entry.y + side * in.x * radius_m};
  const double start_rad = std::atan2(entry.y - centre.y, entry.x - centre.x);
  const int steps =
      std::max(1, static_cast<int>(std::ceil(std::abs(turn_rad) * radius_m / step_m)));
  std::vector<geometry::Point2D> arc;
  arc.reserve(static_cast<std::size_t>(steps) + 1);
  for (int i = 0; i <= steps; ++i) {
    const double angle = start_rad + turn_rad * static_cast<double>(i) / steps;
    arc.push_back({centre.x + radius_m * std::cos(angle), centre.y + radius_m * std::sin(angle)});
  }
  return arc;
}

bool arc_is_clear(const PlanningGrid& grid, geometry::Point2D before,
                  const std::vector<geometry::Point2D>& arc, geometry::Point2D after,
                  std::uint8_t max_cost) {
  geometry::Point2D previous = before;
  for (const geometry::Point2D& point : arc) {
    if (!segment_is_clear(grid, previous, point, max_cost)) return false;
    previous = point;
  }
  return segment_is_clear(grid, previous, after, max_cost);
}

}  // namespace

std::vector<geometry::Point2D> fillet_corners(const PlanningGrid& grid,
                                              const std::vector<geometry::Point2D>& points,
                                              const TurningRadiusFilletOptions& options) {
  if (points.size() < 3 || !(options.min_turning_radius_m > 0.0) || !(options.arc_step_m > 0.0)) {
    return points;
  }
  std::vector<geometry::Point2D> out{points.front()};
  for (std::size_t i = 1; i + 1 < points.size(); ++i) {
    double in_length_m = 0.0;
    double out_length_m = 0.0;
    const Vector in = unit(points[i - 1], points[i], in_length_m);
    const Vector out_dir = unit(points[i], points[i + 1], out_length_m);
    const double turn_rad = std::abs(std::atan2(in.x * out_dir.y - in.y * out_dir.x,
                                                in.x * out_dir.x + in.y * out_dir.y));
    if (!(in_length_m > 0.0) || !(out_length_m > 0.0) || turn_rad < 1e-3 ||
        turn_rad > std::numbers::pi - 1e-3) {
      out.push_back(points[i]);
      continue;
    }
    // A leg between two corners lends each of them half; the first and last legs lend all.
    const double in_budget_m = i == 1 ? in_length_m : in_length_m / 2.0;
    const double out_budget_m = i + 2 == points.size() ? out_length_m : out_length_m / 2.0;
    const double max_tangent_m = std::min(in_budget_m, out_budget_m);
    const double radius_m = std::min(options.min_turning_radius_m,
                                     max_tangent_m / std::tan(turn_rad / 2.0));
    std::vector<geometry::Point2D> arc =
        corner_arc(points[i], in, out_dir, radius_m, options.arc_step_m);
    if (arc_is_clear(grid, out.back(), arc, points[i + 1], options.max_cost)) {
      out.insert(out.end(), arc.begin(), arc.end());
    } else {
      out.push_back(points[i]);
    }
  }
  out.push_back(points.back());
  return out;
}

}  // namespace mobot::planning
