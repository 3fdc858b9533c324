#include "core/planning/voronoi_roadmap.h"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>

#include "core/numeric/integer_division.h"

namespace mobot::planning {
namespace {

constexpr std::int32_t kNoRow = -1;

bool is_site_cost(std::uint8_t cost) {
  return cost == PlanningGrid::kLethal || cost == PlanningGrid::kUnknown;
}

std::int64_t squared(std::int64_t v) { return v * v; }

// Phase 1 of Meijster's transform: for every cell the row of the nearest obstacle in its own
// column, or kNoRow. A tie (as near above as below) goes to the lower row.
std::vector<std::int32_t> nearest_rows_in_columns(const PlanningGrid& grid) {
  const int width = grid.width();
  const int height = grid.height();
  const std::uint8_t* costs = grid.costs().data();
  const auto w = static_cast<std::size_t>(width);
  std::vector<std::int32_t> rows(grid.costs().size(), kNoRow);
  for (int x = 0; x < width; ++x) {
    std::int32_t below = kNoRow;
    for (int y = 0; y < height; ++y) {
      const std::size_t i = static_cast<std::size_t>(y) * w + static_cast<std::size_t>(x);
      if (is_site_cost(costs[i])) below = y;
      rows[i] = below;
    }
    std::int32_t above = kNoRow;
    for (int y = height - 1; y >= 0; --y) {
      const std::size_t i = static_cast<std::size_t>(y) * w + static_cast<std::size_t>(x);
      if (is_site_cost(costs[i])) above = y;
      if (above != kNoRow && (rows[i] == kNoRow || above - y < y - rows[i])) rows[i] = above;
    }
  }
  return rows;
}

}  // namespace

VoronoiRoadmap::VoronoiRoadmap(const PlanningGrid& grid, const VoronoiRoadmapOptions& options) {
  if (!std::isfinite(options.min_passage_width_m) || options.min_passage_width_m < 0.0) {
    throw std::invalid_argument("Voronoi roadmap options must be finite and non-negative");
  }
  if (grid.empty()) return;
  width_ = grid.width();
  height_ = grid.height();
  resolution_m_ = grid.resolution_m();
  compute_sites(grid);

  mask_.assign(grid.costs().size(), 0);
  const double min_separation_cells = options.min_passage_width_m / resolution_m_;
  // A hair below the threshold: site separations are square roots of integers.
  const double min_separation_squared = min_separation_cells * min_separation_cells - 1e-9;
  const auto w = static_cast<std::size_t>(width_);
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      // Each pair once: with the right and the upper neighbour.
      const std::size_t i = static_cast<std::size_t>(y) * w + static_cast<std::size_t>(x);
      if (x + 1 < width_) mark_pair(grid, i, i + 1, min_separation_squared);
      if (y + 1 < height_) mark_pair(grid, i, i + w, min_separation_squared);
    }
  }
  for (const std::uint8_t m : mask_) size_ += m;
}

// Phase 2 of Meijster's transform, per row: the lower envelope of the parabolas
// (x - i)^2 + g(i)^2, one per column i, where g(i) is the distance to the nearest obstacle in
// column i (phase 1). The column of the parabola that is lowest at x, with that column's nearest
// row, is x's nearest obstacle: an exact Euclidean feature transform in integer arithmetic, O(n).
void VoronoiRoadmap::compute_sites(const PlanningGrid& grid) {
  const std::vector<std::int32_t> rows = nearest_rows_in_columns(grid);
  sites_.assign(rows.size(), kNoSite);
  // Larger than any real distance, so a column without obstacles never wins over one with.
  const std::int64_t infinite = std::int64_t{width_} + height_;
  const std::int64_t infinite_squared = squared(infinite);
  std::vector<std::int64_t> g2(static_cast<std::size_t>(width_));
  std::vector<std::int64_t> s(static_cast<std::size_t>(width_));  // envelope: parabola columns
  std::vector<std::int64_t> t(static_cast<std::size_t>(width_));  // and where each starts
  const auto w = static_cast<std::size_t>(width_);
  for (int y = 0; y < height_; ++y) {
    const std::size_t row_offset = static_cast<std::size_t>(y) * w;
    for (std::size_t x = 0; x < w; ++x) {
      const std::int32_t r = rows[row_offset + x];
      g2[x] = r == kNoRow ? infinite_squared : squared(y - r);
    }
    const auto f = [&g2](std::int64_t x, std::int64_t i) {
      return squared(x - i) + g2[static_cast<std::size_t>(i)];
    };
    // The first x at which parabola u is strictly below parabola i < u, minus one.
    const auto separation = [&g2](std::int64_t i, std::int64_t u) {
      return floor_div(squared(u) - squared(i) + g2[static_cast<std::size_t>(u)] -
                           g2[static_cast<std::size_t>(i)],
                       2 * (u - i));
    };
    std::int64_t q = 0;
    s[0] = 0;
    t[0] = 0;
    for (std::int64_t u = 1; u < width_; ++u) {
      // Equal values keep the earlier column: the ties are broken the same way on every run.
      while (q >= 0 && f(t[static_cast<std::size_t>(q)], s[static_cast<std::size_t>(q)]) >
                           f(t[static_cast<std::size_t>(q)], u)) {
        --q;
      }
      if (q < 0) {
        q = 0;
        s[0] = u;
        continue;
      }
      const std::int64_t start = 1 + separation(s[static_cast<std::size_t>(q)], u);
      if (start < width_) {
        ++q;
        s[static_cast<std::size_t>(q)] = u;
        t[static_cast<std::size_t>(q)] = start;
      }
    }
    for (std::int64_t x = width_ - 1; x >= 0; --x) {
      const std::int64_t column = s[static_cast<std::size_t>(q)];
      if (f(x, column) < infinite_squared) {
        const std::int32_t site_row = rows[row_offset + static_cast<std::size_t>(column)];
        sites_[row_offset + static_cast<std::size_t>(x)] = static_cast<std::uint32_t>(
            static_cast<std::size_t>(site_row) * w + static_cast<std::size_t>(column));
      }
      if (x == t[static_cast<std::size_t>(q)]) --q;
    }
  }
}

void VoronoiRoadmap::mark_pair(const PlanningGrid& grid, std::size_t a, std::size_t b,
                               double min_separation_squared_cells) {
  const std::uint32_t site_a = sites_[a];
  const std::uint32_t site_b = sites_[b];
  if (site_a == kNoSite || site_b == kNoSite || site_a == site_b) return;
  const mapping::CellIndex sa = grid.cell_of(site_a);
  const mapping::CellIndex sb = grid.cell_of(site_b);
  const int sdx = std::abs(sa.x - sb.x);
  const int sdy = std::abs(sa.y - sb.y);
  // Adjacent sites are one stretch of one obstacle: no bisector between them.
  if (sdx <= 1 && sdy <= 1) return;
  if (static_cast<double>(squared(sdx) + squared(sdy)) < min_separation_squared_cells) return;

  const mapping::CellIndex ca = grid.cell_of(a);
  const mapping::CellIndex cb = grid.cell_of(b);
  const auto distance_squared = [](mapping::CellIndex c, mapping::CellIndex site) {
    return squared(c.x - site.x) + squared(c.y - site.y);
  };
  // How much farther each cell is from the other's site than from its own (never negative with an
  // exact transform): the smaller, the nearer the bisector.
  const std::int64_t margin_a = distance_squared(ca, sb) - distance_squared(ca, sa);
  const std::int64_t margin_b = distance_squared(cb, sa) - distance_squared(cb, sb);
  // On a tie (the bisector halfway between the two) a is the cell with the lower index.
  const std::size_t marked = margin_a <= margin_b ? a : b;
  if (PlanningGrid::is_traversable_cost(grid.costs()[marked])) mask_[marked] = 1;
}

std::optional<mapping::CellIndex> VoronoiRoadmap::site_of(mapping::CellIndex cell) const {
  if (!contains(cell)) return std::nullopt;
  const std::uint32_t site = sites_[index_of(cell)];
  if (site == kNoSite) return std::nullopt;
  const auto w = static_cast<std::uint32_t>(width_);
  return mapping::CellIndex{static_cast<int>(site % w), static_cast<int>(site / w)};
}

double VoronoiRoadmap::clearance_cells(mapping::CellIndex cell) const {
  const auto site = site_of(cell);
  if (!site) return std::numeric_limits<double>::infinity();
  return std::hypot(cell.x - site->x, cell.y - site->y);
}

}  // namespace mobot::planning
