#include "core/planning/planning_grid_builder.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

namespace mobot::planning {
namespace {

// In the distance-transform input a zero pixel is an obstacle (the distance source).
constexpr std::uint8_t kSourcePixel = 0;
constexpr std::uint8_t kClearPixel = 255;

bool is_valid_length(double value) { return std::isfinite(value) && value >= 0.0; }

constexpr std::uint8_t kExtraObstacle = 1;

// Marks every planning cell whose centre an occupied cell of `extra` covers, plus the planning cell
// under that cell's centre, in `marks` (same layout as `grid`).
void mark_extra_grid(const PlanningGrid& grid, const mapping::OccupancyGrid& extra,
                     cv::Mat& marks) {
  if (extra.width() <= 0 || extra.height() <= 0) return;
  const geometry::Pose2D grid_from_map = geometry::inverse(grid.origin());
  const geometry::Pose2D extra_from_map = geometry::inverse(extra.origin());
  const double res = grid.resolution_m();
  const double extra_res = extra.resolution_m();
  for (int ey = 0; ey < extra.height(); ++ey) {
    for (int ex = 0; ex < extra.width(); ++ex) {
      const mapping::CellIndex extra_cell{ex, ey};
      if (!extra.is_occupied(extra_cell)) continue;
      if (const auto centre = grid.cell_at(extra.cell_center(extra_cell))) {
        marks.at<std::uint8_t>(centre->y, centre->x) = kExtraObstacle;
      }
      // Bounding box of the extra cell's corners in planning-grid cells.
      double min_x = grid.width();
      double min_y = grid.height();
      double max_x = -1.0;
      double max_y = -1.0;
      for (const auto& [cx, cy] : {std::pair{0, 0}, {1, 0}, {0, 1}, {1, 1}}) {
        const geometry::Point2D corner_in_extra{(ex + cx) * extra_res, (ey + cy) * extra_res};
        const geometry::Point2D corner_in_grid = geometry::transform_point(
            grid_from_map, geometry::transform_point(extra.origin(), corner_in_extra));
        min_x = std::min(min_x, corner_in_grid.x / res);
        min_y = std::min(min_y, corner_in_grid.y / res);
        max_x = std::max(max_x, corner_in_grid.x / res);
        max_y = std::max(max_y, corner_in_grid.y / res);
      }
      const int x0 = std::max(0, static_cast<int>(std::floor(min_x)));
      const int y0 = std::max(0, static_cast<int>(std::floor(min_y)));
      const int x1 = std::min(grid.width() - 1, static_cast<int>(std::floor(max_x)));
      const int y1 = std::min(grid.height() - 1, static_cast<int>(std::floor(max_y)));
      for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
          const geometry::Point2D in_extra =
              geometry::transform_point(extra_from_map, grid.cell_center({x, y}));
          if (static_cast<int>(std::floor(in_extra.x / extra_res)) == ex &&
              static_cast<int>(std::floor(in_extra.y / extra_res)) == ey) {
            marks.at<std::uint8_t>(y, x) = kExtraObstacle;
          }
        }
      }
    }
  }
}

}  // namespace

PlanningGridBuilder::PlanningGridBuilder(const PlanningGridOptions& options) : options_(options) {
  if (!is_valid_length(options.inscribed_radius_m) ||
      !is_valid_length(options.inflation_margin_m) ||
      !is_valid_length(options.cost_scaling_per_m)) {
    throw std::invalid_argument("planning grid options must be finite and non-negative");
  }
}

std::uint8_t PlanningGridBuilder::cost_at_distance(double distance_m) const {
  // Cell distances are multiples of the resolution: 6 x 0.05 must count as 0.30, not 0.30000001.
  constexpr double kEpsilonM = 1e-9;
  if (distance_m <= 0.0) return PlanningGrid::kLethal;
  if (distance_m <= options_.inscribed_radius_m + kEpsilonM) return PlanningGrid::kInscribed;
  const double beyond_m = std::max(0.0, distance_m - options_.inscribed_radius_m);
  if (beyond_m > options_.inflation_margin_m + kEpsilonM) return PlanningGrid::kFree;
  const double factor = std::exp(-options_.cost_scaling_per_m * beyond_m);
  return static_cast<std::uint8_t>(std::lround((PlanningGrid::kInscribed - 1) * factor) & 0xFF);
}

PlanningGrid PlanningGridBuilder::build(const mapping::OccupancyGrid& occupancy,
                                        const ExtraObstacles& extra) const {
  if (occupancy.width() <= 0 || occupancy.height() <= 0 || occupancy.cells().empty()) return {};
  PlanningGrid grid(occupancy.width(), occupancy.height(), occupancy.resolution_m(),
                    occupancy.origin(), PlanningGrid::kFree);
  const int width = grid.width();
  const int height = grid.height();

  // Row y of the mask is row y of the grid (no image flip: only distances matter here).
  cv::Mat mask(height, width, CV_8UC1);
  const std::vector<std::uint8_t>& cells = occupancy.cells();
  for (int y = 0; y < height; ++y) {
    auto* row = mask.ptr<std::uint8_t>(y);
    const std::size_t offset = static_cast<std::size_t>(y) * static_cast<std::size_t>(width);
    for (int x = 0; x < width; ++x) {
      const std::uint8_t value = cells[offset + static_cast<std::size_t>(x)];
      const bool unknown = value == mapping::OccupancyGrid::kUnknown;
      const bool source =
          unknown ? options_.unknown_is_obstacle : value >= options_.occupied_threshold;
      row[x] = source ? kSourcePixel : kClearPixel;
    }
  }
  // Extra obstacles are kept apart too, so an obstacle seen in unknown space becomes lethal.
  cv::Mat extra_marks;
  if (!extra.grids.empty() || !extra.points_in_map.empty()) {
    extra_marks = cv::Mat::zeros(height, width, CV_8UC1);
    for (const auto& extra_grid : extra.grids) mark_extra_grid(grid, extra_grid, extra_marks);
    for (const auto& point : extra.points_in_map) {
      if (const auto cell = grid.cell_at(point)) {
        extra_marks.at<std::uint8_t>(cell->y, cell->x) = kExtraObstacle;
      }
    }
    mask.setTo(kSourcePixel, extra_marks);
  }

  cv::Mat distance_cells;
  cv::distanceTransform(mask, distance_cells, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);

  // The exact transform yields sqrt of an integer squared distance, so a table indexed by the
  // squared distance (in cells^2) is exact and avoids an exp() per cell.
  const double res = grid.resolution_m();
  const double inflation_radius_cells =
      (options_.inscribed_radius_m + options_.inflation_margin_m) / res;
  const auto max_squared =
      static_cast<int>(std::ceil(inflation_radius_cells * inflation_radius_cells)) + 1;
  std::vector<std::uint8_t> cost_by_squared(static_cast<std::size_t>(max_squared) + 1);
  for (int d2 = 0; d2 <= max_squared; ++d2) {
    cost_by_squared[static_cast<std::size_t>(d2)] = cost_at_distance(std::sqrt(d2) * res);
  }

  std::vector<std::uint8_t>& costs = grid.mutable_costs();
  for (int y = 0; y < height; ++y) {
    const auto* distance_row = distance_cells.ptr<float>(y);
    const auto* mask_row = mask.ptr<std::uint8_t>(y);
    const std::size_t offset = static_cast<std::size_t>(y) * static_cast<std::size_t>(width);
    for (int x = 0; x < width; ++x) {
      const std::size_t index = offset + static_cast<std::size_t>(x);
      if (mask_row[x] == kSourcePixel) {
        const bool extra_obstacle =
            !extra_marks.empty() && extra_marks.at<std::uint8_t>(y, x) == kExtraObstacle;
        const bool unknown = cells[index] == mapping::OccupancyGrid::kUnknown && !extra_obstacle;
        costs[index] = unknown ? PlanningGrid::kUnknown : PlanningGrid::kLethal;
        continue;
      }
      const double d = distance_row[x];
      const double squared = d * d;
      costs[index] = squared > max_squared
                         ? PlanningGrid::kFree
                         : cost_by_squared[static_cast<std::size_t>(std::lround(squared))];
    }
  }
  return grid;
}

}  // namespace mobot::planning
