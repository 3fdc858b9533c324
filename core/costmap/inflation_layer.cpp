#include "core/costmap/inflation_layer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/numeric/finite.h"
#include "core/numeric/integer_division.h"

namespace mobot::costmap {
namespace {

using planning::PlanningGrid;

}  // namespace

InflationLayer::InflationLayer(const InflationLayerOptions& options) : options_(options) {
  if (!finite_non_negative(options.inscribed_radius_m) ||
      !finite_non_negative(options.inflation_radius_m) ||
      !finite_non_negative(options.cost_scaling_per_m)) {
    throw std::invalid_argument("inflation options must be finite and non-negative");
  }
}

std::uint8_t InflationLayer::cost_at_distance(double distance_m) const {
  // Cell distances are multiples of the resolution: 6 x 0.05 must count as 0.30, not 0.30000001.
  constexpr double kEpsilonM = 1e-9;
  if (distance_m <= 0.0) return PlanningGrid::kLethal;
  if (distance_m <= options_.inscribed_radius_m + kEpsilonM) return PlanningGrid::kInscribed;
  if (distance_m > options_.inflation_radius_m + kEpsilonM) return PlanningGrid::kFree;
  const double factor =
      std::exp(-options_.cost_scaling_per_m * (distance_m - options_.inscribed_radius_m));
  return static_cast<std::uint8_t>(std::lround(PlanningGrid::kMaxInflated * factor) & 0xFF);
}

int InflationLayer::reach_cells(double resolution_m) const {
  const double radius_m = std::max(options_.inscribed_radius_m, options_.inflation_radius_m);
  return static_cast<int>(std::ceil(radius_m / resolution_m - 1e-9)) + 1;
}

void InflationLayer::prepare(double resolution_m) {
  if (resolution_m == prepared_resolution_m_) return;
  prepared_resolution_m_ = resolution_m;
  reach_ = reach_cells(resolution_m);
  const auto max_squared = static_cast<std::size_t>(reach_) * static_cast<std::size_t>(reach_);
  cost_by_squared_cells_.resize(max_squared + 1);
  for (std::size_t d2 = 0; d2 <= max_squared; ++d2) {
    cost_by_squared_cells_[d2] =
        cost_at_distance(std::sqrt(static_cast<double>(d2)) * resolution_m);
  }
}

void InflationLayer::inflate(PlanningGrid& grid, const CellBounds& bounds) {
  const CellBounds b = bounds.clipped(grid.width(), grid.height());
  if (b.empty()) return;
  prepare(grid.resolution_m());
  const int reach = reach_;
  const CellBounds s = b.expanded(reach).clipped(grid.width(), grid.height());
  const int sw = s.width();
  const int sh = s.height();
  std::vector<std::uint8_t>& costs = grid.mutable_costs();

  // Pass 1: vertical distance (in cells) to the nearest source in the same column, capped at
  // reach + 1 ("too far to matter"). Row by row, so the inner loops run along memory; in blocks of
  // kLanes through a local buffer, which the compiler turns into vector code.
  const auto far = static_cast<std::uint16_t>(reach + 1);
  const std::uint8_t other_source =
      options_.inflate_unknown ? PlanningGrid::kUnknown : PlanningGrid::kLethal;
  column_cells_.resize(static_cast<std::size_t>(sw) * static_cast<std::size_t>(sh));
  std::uint16_t* g = column_cells_.data();
  const auto next_from = [far, other_source](std::uint8_t cost, std::uint16_t below) {
    const bool source = cost == PlanningGrid::kLethal || cost == other_source;
    const auto next = std::min<std::uint16_t>(static_cast<std::uint16_t>(below + 1), far);
    return source ? std::uint16_t{0} : next;
  };
  constexpr int kLanes = 16;
  for (int j = 0; j < sh; ++j) {
    const std::uint8_t* src = costs.data() + grid.index_of({s.min_x, s.min_y + j});
    std::uint16_t* out = g + static_cast<std::ptrdiff_t>(j) * sw;
    // The row below the region counts as "far": sources outside it are out of reach.
    const std::uint16_t* below = j == 0 ? nullptr : out - sw;
    int i = 0;
    for (; below != nullptr && i + kLanes <= sw; i += kLanes) {
      std::uint16_t block[kLanes];
      for (int l = 0; l < kLanes; ++l) block[l] = next_from(src[i + l], below[i + l]);
      std::copy(block, block + kLanes, out + i);
    }
    for (; i < sw; ++i) out[i] = next_from(src[i], below == nullptr ? far : below[i]);
  }
  for (int j = sh - 2; j >= 0; --j) {
    std::uint16_t* out = g + static_cast<std::ptrdiff_t>(j) * sw;
    const std::uint16_t* above = out + sw;
    int i = 0;
    for (; i + kLanes <= sw; i += kLanes) {
      std::uint16_t block[kLanes];
      for (int l = 0; l < kLanes; ++l) {
        block[l] =
            std::min<std::uint16_t>(out[i + l], static_cast<std::uint16_t>(above[i + l] + 1));
      }
      std::copy(block, block + kLanes, out + i);
    }
    for (; i < sw; ++i) {
      out[i] = std::min<std::uint16_t>(out[i], static_cast<std::uint16_t>(above[i] + 1));
    }
  }

  // Pass 2, per row of the bounds: d2(x) = min over sites x' of (x - x')^2 + g(x')^2, the lower
  // envelope of parabolas. Boundaries between envelope pieces are kept as fractions num / den
  // (den > 0), compared by cross-multiplication, so the result is exact.
  site_x_.resize(static_cast<std::size_t>(sw));
  site_value_.resize(static_cast<std::size_t>(sw));
  boundary_num_.resize(static_cast<std::size_t>(sw) + 1);
  boundary_den_.resize(static_cast<std::size_t>(sw) + 1);
  int* vx = site_x_.data();
  std::int64_t* vf = site_value_.data();  // g^2 + x^2 of the site
  std::int64_t* zn = boundary_num_.data();
  std::int64_t* zd = boundary_den_.data();
  const std::uint8_t* table = cost_by_squared_cells_.data();
  const std::int64_t max_squared = static_cast<std::int64_t>(reach) * reach;
  for (int y = b.min_y; y <= b.max_y; ++y) {
    const std::uint16_t* row = g + static_cast<std::ptrdiff_t>(y - s.min_y) * sw;
    int k = -1;  // index of the last envelope piece; piece j covers x in (z[j], z[j + 1]]
    for (int q = 0; q < sw; ++q) {
      if (row[q] > reach) continue;
      const std::int64_t fq =
          static_cast<std::int64_t>(row[q]) * row[q] + static_cast<std::int64_t>(q) * q;
      while (k >= 0) {
        const std::int64_t num = fq - vf[k];
        const std::int64_t den = 2 * static_cast<std::int64_t>(q - vx[k]);
        // The new parabola takes over from piece k at num / den; piece k is hidden when that is
        // at or before where piece k itself began.
        if (k > 0 && num * zd[k] <= zn[k] * den) {
          --k;
          continue;
        }
        ++k;
        vx[k] = q;
        vf[k] = fq;
        zn[k] = num;
        zd[k] = den;
        break;
      }
      if (k < 0) {
        k = 0;
        vx[0] = q;
        vf[0] = fq;
      }
    }
    if (k < 0) continue;  // no source within reach of this row
    // Each envelope piece j rules x in (z[j], z[j + 1]]; only the part within `reach` of its site
    // can be inflated, so rows far from every obstacle cost a visit per piece, not per cell.
    std::uint8_t* out = costs.data() + grid.index_of({s.min_x, y});
    const int first = b.min_x - s.min_x;
    const int last = b.max_x - s.min_x;
    for (int j = 0; j <= k; ++j) {
      // The piece's integer range: x > z[j] and x <= z[j + 1] (z as num / den, den > 0).
      int lo = j == 0 ? first : static_cast<int>(floor_div(zn[j], zd[j])) + 1;
      int hi = j == k ? last : static_cast<int>(floor_div(zn[j + 1], zd[j + 1]));
      lo = std::max({lo, first, vx[j] - reach});
      hi = std::min({hi, last, vx[j] + reach});
      const std::int64_t g2 = vf[j] - static_cast<std::int64_t>(vx[j]) * vx[j];
      for (int i = lo; i <= hi; ++i) {
        const std::int64_t dx = i - vx[j];
        const std::int64_t d2 = dx * dx + g2;
        if (d2 > max_squared) continue;
        const std::uint8_t cost = table[d2];
        std::uint8_t& cell = out[i];
        if (cell != PlanningGrid::kUnknown && cost > cell) cell = cost;
      }
    }
  }
}

void InflationLayer::match_geometry(const PlanningGrid& master) {
  if (!master.empty()) prepare(master.resolution_m());
}

void InflationLayer::shift(const PlanningGrid& /*master*/, int /*dx_cells*/, int /*dy_cells*/) {}

void InflationLayer::update_bounds(const PlanningGrid& master, CellBounds& bounds) {
  if (master.empty() || bounds.empty()) return;
  bounds = bounds.expanded(reach_cells(master.resolution_m()));
}

void InflationLayer::update(PlanningGrid& master, const CellBounds& bounds) {
  inflate(master, bounds);
}

}  // namespace mobot::costmap
