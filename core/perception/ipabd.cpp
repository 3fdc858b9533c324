#include "core/perception/ipabd.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/numeric/constants.h"

namespace mobot::perception {
namespace {

constexpr std::size_t kMaxBinGap = 2;  // empty bins a segment may span

void require_positive(double value, const char* name) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw std::invalid_argument(std::string("IPaBD option ") + name + " must be positive");
  }
}

void validate(const IpabdOptions& options) {
  require_positive(options.robot_height_m, "robot_height_m");
  require_positive(options.bearing_step_rad, "bearing_step_rad");
  require_positive(options.max_range_m, "max_range_m");
  require_positive(options.robot_diameter_m, "robot_diameter_m");
  if (!(options.floor_tolerance_m >= 0.0) || !(options.dilation_radius_m >= 0.0) ||
      !(options.pdbs_c0_m >= 0.0) || !(options.pdbs_c1 >= 0.0) ||
      !std::isfinite(options.floor_tolerance_m + options.dilation_radius_m + options.pdbs_c0_m +
                     options.pdbs_c1)) {
    throw std::invalid_argument("IPaBD tolerances must be finite and not negative");
  }
}

// A square grid of side 2 * max_range around the origin, its corners on the lattice when given.
mapping::OccupancyGrid empty_grid(geometry::Point2D origin, const IpabdOptions& options) {
  const double cell_m = options.cell_m();
  double min_x_m = origin.x - options.max_range_m;
  double min_y_m = origin.y - options.max_range_m;
  if (options.lattice_origin) {
    min_x_m = options.lattice_origin->x +
              std::floor((min_x_m - options.lattice_origin->x) / cell_m) * cell_m;
    min_y_m = options.lattice_origin->y +
              std::floor((min_y_m - options.lattice_origin->y) / cell_m) * cell_m;
  }
  const int cells = static_cast<int>(std::ceil(2.0 * options.max_range_m / cell_m)) + 1;
  return {cells, cells, cell_m, {min_x_m, min_y_m, 0.0}, mapping::OccupancyGrid::kUnknown};
}

struct BinState {
  double nearest_m = std::numeric_limits<double>::infinity();
  geometry::Point2D nearest_point;
  double farthest_floor_m = 0.0;
};

// Steps 1 and 2: height filter first, so a beam above the robot never hides a low obstacle behind
// it in the nearest-point step.
std::vector<BinState> bin_points(std::span<const CloudPoint> cloud, geometry::Point2D origin,
                                 const IpabdOptions& options, IpabdResult& result) {
  const auto bin_count = static_cast<std::size_t>(std::ceil(kTwoPi / options.bearing_step_rad));
  std::vector<BinState> bins(bin_count);
  result.points_in = cloud.size();
  for (const CloudPoint& point : cloud) {
    const double dx_m = point.x_m - origin.x;
    const double dy_m = point.y_m - origin.y;
    const double range_m = std::hypot(dx_m, dy_m);
    if (!(range_m <= options.max_range_m)) {
      ++result.points_out_of_range;
      continue;
    }
    auto bin = static_cast<std::size_t>((std::atan2(dy_m, dx_m) + std::numbers::pi) /
                                        options.bearing_step_rad);
    bin = std::min(bin, bin_count - 1);
    BinState& state = bins[bin];
    if (point.z_m > options.robot_height_m) {
      ++result.points_above;
    } else if (std::abs(point.z_m) < options.floor_tolerance_m) {
      ++result.points_floor;
      state.farthest_floor_m = std::max(state.farthest_floor_m, range_m);
    } else if (range_m < state.nearest_m) {
      state.nearest_m = range_m;
      state.nearest_point = {point.x_m, point.y_m};
    }
  }
  return bins;
}

// Step 3: PDBS over bins that hold a point, consecutive in bearing (wrapping around).
std::vector<IpabdSegment> segment_bins(const std::vector<IpabdResult::Bin>& bins,
                                       std::size_t bin_count, const IpabdOptions& options) {
  std::vector<IpabdSegment> segments;
  if (bins.empty()) return segments;
  const auto joined = [&](const IpabdResult::Bin& a, const IpabdResult::Bin& b) {
    // Bins and beams do not line up one to one, so a bin between two beams can stay empty.
    if ((b.index + bin_count - a.index) % bin_count > kMaxBinGap + 1) return false;
    const double gap_m = std::abs(a.range_m - b.range_m);
    return gap_m <= options.pdbs_c0_m + options.pdbs_c1 * std::min(a.range_m, b.range_m);
  };
  for (std::size_t i = 0; i < bins.size(); ++i) {
    if (i > 0 && joined(bins[i - 1], bins[i])) {
      ++segments.back().bins;
    } else {
      segments.push_back({i, 1});
    }
  }
  // The last segment continues into the first across the -pi/pi seam.
  if (segments.size() > 1 && joined(bins.back(), bins.front())) {
    segments.front().first_bin = segments.back().first_bin;
    segments.front().bins += segments.back().bins;
    segments.pop_back();
  }
  return segments;
}

void mark_line(mapping::OccupancyGrid& grid, geometry::Point2D from, geometry::Point2D to,
               std::uint8_t value, bool overwrite_occupied) {
  const double length_m = std::hypot(to.x - from.x, to.y - from.y);
  const int steps = std::max(1, static_cast<int>(std::ceil(2.0 * length_m / grid.resolution_m())));
  for (int i = 0; i <= steps; ++i) {
    const double f = static_cast<double>(i) / steps;
    const auto cell = grid.cell_at({from.x + f * (to.x - from.x), from.y + f * (to.y - from.y)});
    if (!cell) continue;
    if (!overwrite_occupied && grid.at(*cell) == mapping::OccupancyGrid::kOccupied) continue;
    grid.set(*cell, value);
  }
}

void dilate(const mapping::OccupancyGrid& obstacles, double radius_m,
            mapping::OccupancyGrid& dilated) {
  dilated = obstacles;
  const int reach = static_cast<int>(std::floor(radius_m / obstacles.resolution_m()));
  const double reach_sq = std::pow(radius_m / obstacles.resolution_m(), 2);
  for (int y = 0; y < obstacles.height(); ++y) {
    for (int x = 0; x < obstacles.width(); ++x) {
      if (obstacles.at({x, y}) != mapping::OccupancyGrid::kOccupied) continue;
      for (int dy = -reach; dy <= reach; ++dy) {
        for (int dx = -reach; dx <= reach; ++dx) {
          const mapping::CellIndex cell{x + dx, y + dy};
          if (dx * dx + dy * dy <= reach_sq && dilated.contains(cell)) {
            dilated.set(cell, mapping::OccupancyGrid::kOccupied);
          }
        }
      }
    }
  }
}

}  // namespace

IpabdResult run_ipabd(std::span<const CloudPoint> cloud, geometry::Point2D origin_in_map,
                      const IpabdOptions& options) {
  validate(options);
  IpabdResult result;
  const std::vector<BinState> states = bin_points(cloud, origin_in_map, options, result);
  for (std::size_t i = 0; i < states.size(); ++i) {
    if (std::isfinite(states[i].nearest_m)) {
      result.bins.push_back({i, static_cast<float>(states[i].nearest_m), states[i].nearest_point});
    }
  }
  result.obstacles = empty_grid(origin_in_map, options);
  // Free space first: along each bearing up to its first obstacle, or as far as it saw floor.
  for (std::size_t i = 0; i < states.size(); ++i) {
    const double free_m = std::isfinite(states[i].nearest_m)
                              ? states[i].nearest_m - options.cell_m()
                              : states[i].farthest_floor_m;
    if (free_m <= 0.0) continue;
    const double bearing_rad =
        -std::numbers::pi + (static_cast<double>(i) + 0.5) * options.bearing_step_rad;
    mark_line(result.obstacles, origin_in_map,
              {origin_in_map.x + free_m * std::cos(bearing_rad),
               origin_in_map.y + free_m * std::sin(bearing_rad)},
              mapping::OccupancyGrid::kFree, false);
  }
  if (options.segment) {
    result.segments = segment_bins(result.bins, states.size(), options);
    for (const IpabdSegment& segment : result.segments) {
      for (std::size_t k = 0; k + 1 < segment.bins; ++k) {
        const auto& a = result.bins[(segment.first_bin + k) % result.bins.size()];
        const auto& b = result.bins[(segment.first_bin + k + 1) % result.bins.size()];
        mark_line(result.obstacles, a.point_in_map, b.point_in_map,
                  mapping::OccupancyGrid::kOccupied, true);
      }
    }
  }
  for (const auto& bin : result.bins) {
    if (const auto cell = result.obstacles.cell_at(bin.point_in_map)) {
      result.obstacles.set(*cell, mapping::OccupancyGrid::kOccupied);
    }
  }
  dilate(result.obstacles, options.dilation_radius_m, result.dilated);
  return result;
}

}  // namespace mobot::perception
