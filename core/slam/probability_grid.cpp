#include "core/slam/probability_grid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace mobot::slam {

GridLimits GridLimits::covering(std::span<const geometry::Point2D> points, double resolution_m,
                                double margin_m) {
  if (!(resolution_m > 0.0) || !std::isfinite(resolution_m) || !(margin_m >= 0.0)) {
    throw std::invalid_argument("GridLimits::covering: resolution must be > 0, margin >= 0");
  }
  double min_x = std::numeric_limits<double>::infinity();
  double min_y = min_x;
  double max_x = -min_x;
  double max_y = -min_x;
  for (const auto& p : points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
    min_x = std::min(min_x, p.x);
    min_y = std::min(min_y, p.y);
    max_x = std::max(max_x, p.x);
    max_y = std::max(max_y, p.y);
  }
  GridLimits limits;
  limits.resolution_m = resolution_m;
  if (!(min_x <= max_x)) return limits;
  // Origins on multiples of the resolution: grids built from the same scans at different times
  // then share cell boundaries, which keeps matching results independent of the bounding box.
  limits.origin_x_m = std::floor((min_x - margin_m) / resolution_m) * resolution_m;
  limits.origin_y_m = std::floor((min_y - margin_m) / resolution_m) * resolution_m;
  limits.width = static_cast<int>(std::ceil((max_x + margin_m - limits.origin_x_m) / resolution_m));
  limits.height =
      static_cast<int>(std::ceil((max_y + margin_m - limits.origin_y_m) / resolution_m));
  return limits;
}

ProbabilityGrid::ProbabilityGrid(const GridLimits& limits) : limits_(limits) {
  if (limits.width < 0 || limits.height < 0 || !(limits.resolution_m > 0.0) ||
      !std::isfinite(limits.resolution_m) || !std::isfinite(limits.origin_x_m) ||
      !std::isfinite(limits.origin_y_m)) {
    throw std::invalid_argument("ProbabilityGrid: sizes >= 0, finite origin, resolution > 0");
  }
  cells_.assign(static_cast<std::size_t>(limits.width) * static_cast<std::size_t>(limits.height),
                0.0F);
}

void ProbabilityGrid::smear_points(std::span<const geometry::Point2D> points_in_map,
                                   double sigma_m) {
  if (!(sigma_m > 0.0) || !std::isfinite(sigma_m)) {
    throw std::invalid_argument("ProbabilityGrid::smear_points: sigma must be > 0");
  }
  if (cells_.empty()) return;
  const double res = limits_.resolution_m;
  const int radius = std::max(1, static_cast<int>(std::ceil(3.0 * sigma_m / res)));
  const double inv_two_sigma2 = 1.0 / (2.0 * sigma_m * sigma_m);
  // The Gaussian is separable, and a point's offset within its cell is quantised to 1/16 of a
  // cell (3 mm at 0.05 m): one table of 1-D weights then serves every point without an exp.
  constexpr int kBins = 16;
  const int taps = 2 * radius + 1;
  std::vector<float> table(static_cast<std::size_t>(kBins * taps));
  for (int bin = 0; bin < kBins; ++bin) {
    const double frac = (bin + 0.5) / kBins - 0.5;  // the point's offset from its cell's centre
    for (int k = -radius; k <= radius; ++k) {
      const double d = (k - frac) * res;
      table[static_cast<std::size_t>(bin * taps + k + radius)] =
          static_cast<float>(std::exp(-d * d * inv_two_sigma2));
    }
  }
  auto weights_of = [&](double c, int& centre) {
    centre = static_cast<int>(std::lround(c));
    int bin = static_cast<int>(std::floor((c - centre + 0.5) * kBins));
    bin = std::clamp(bin, 0, kBins - 1);
    return &table[static_cast<std::size_t>(bin * taps)];
  };
  for (const auto& p : points_in_map) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
    const double cx = limits_.to_cell_x(p.x);
    const double cy = limits_.to_cell_y(p.y);
    if (cx < -radius - 1.0 || cy < -radius - 1.0 || cx > limits_.width + radius ||
        cy > limits_.height + radius) {
      continue;
    }
    int ix = 0;
    int iy = 0;
    const float* wx = weights_of(cx, ix);
    const float* wy = weights_of(cy, iy);
    const int y0 = std::max(0, iy - radius);
    const int y1 = std::min(limits_.height - 1, iy + radius);
    const int x0 = std::max(0, ix - radius);
    const int x1 = std::min(limits_.width - 1, ix + radius);
    for (int y = y0; y <= y1; ++y) {
      const float w = wy[y - iy + radius];
      float* row = &cells_[index(0, y)];
      for (int x = x0; x <= x1; ++x) row[x] = std::max(row[x], w * wx[x - ix + radius]);
    }
  }
}

namespace {

// Distance of `point` from the line through `a` and `b` (infinite when they coincide).
double distance_to_line(const geometry::Point2D& point, const geometry::Point2D& a,
                        const geometry::Point2D& b) {
  const double ex = b.x - a.x, ey = b.y - a.y;
  const double length = std::hypot(ex, ey);
  if (!(length > 0.0)) return std::numeric_limits<double>::infinity();
  return std::abs(ex * (point.y - a.y) - ey * (point.x - a.x)) / length;
}

}  // namespace

void ProbabilityGrid::smear_polyline(std::span<const geometry::Point2D> points_in_map,
                                     double sigma_m, double max_gap_m,
                                     double max_collinear_gap_m, double collinear_tolerance_m) {
  if (!(sigma_m > 0.0) || !std::isfinite(sigma_m) || !(max_gap_m >= 0.0) ||
      !(max_collinear_gap_m >= 0.0) || !(collinear_tolerance_m >= 0.0)) {
    throw std::invalid_argument(
        "ProbabilityGrid::smear_polyline: sigma > 0, gaps and tolerance >= 0");
  }
  if (cells_.empty()) return;
  const double res = limits_.resolution_m;
  const double reach_m = 3.0 * sigma_m;
  const double reach2 = reach_m * reach_m;
  // exp(-d^2 / 2 sigma^2) tabulated over d^2 in [0, (3 sigma)^2].
  constexpr int kTable = 512;
  std::array<float, kTable + 1> table{};
  for (int i = 0; i <= kTable; ++i) {
    const double d2 = reach2 * i / kTable;
    table[static_cast<std::size_t>(i)] =
        static_cast<float>(std::exp(-d2 / (2.0 * sigma_m * sigma_m)));
  }
  const double to_index = kTable / reach2;
  auto smear_segment = [&](const geometry::Point2D& a, const geometry::Point2D& b) {
    const double ax = limits_.to_cell_x(a.x) * res, ay = limits_.to_cell_y(a.y) * res;
    const double bx = limits_.to_cell_x(b.x) * res, by = limits_.to_cell_y(b.y) * res;
    const double ex = bx - ax, ey = by - ay;
    const double length2 = ex * ex + ey * ey;
    const int x0 = std::max(0, static_cast<int>(std::floor((std::min(ax, bx) - reach_m) / res)));
    const int x1 = std::min(limits_.width - 1,
                            static_cast<int>(std::ceil((std::max(ax, bx) + reach_m) / res)));
    const int y0 = std::max(0, static_cast<int>(std::floor((std::min(ay, by) - reach_m) / res)));
    const int y1 = std::min(limits_.height - 1,
                            static_cast<int>(std::ceil((std::max(ay, by) + reach_m) / res)));
    for (int y = y0; y <= y1; ++y) {
      float* row = &cells_[index(0, y)];
      const double py = y * res - ay;
      for (int x = x0; x <= x1; ++x) {
        const double px = x * res - ax;
        double t = length2 > 0.0 ? (px * ex + py * ey) / length2 : 0.0;
        t = std::clamp(t, 0.0, 1.0);
        const double dx = px - t * ex, dy = py - t * ey;
        const double d2 = dx * dx + dy * dy;
        if (d2 >= reach2) continue;
        row[x] = std::max(row[x], table[static_cast<std::size_t>(d2 * to_index)]);
      }
    }
  };
  const double max_gap2 = max_gap_m * max_gap_m;
  const double max_collinear_gap2 = max_collinear_gap_m * max_collinear_gap_m;
  const std::size_t n = points_in_map.size();
  auto finite = [&](std::size_t k) {
    return std::isfinite(points_in_map[k].x) && std::isfinite(points_in_map[k].y);
  };
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = points_in_map[i];
    if (!finite(i)) continue;
    bool joined = false;
    if (i + 1 < n && finite(i + 1)) {
      const auto& q = points_in_map[i + 1];
      const double gx = q.x - p.x, gy = q.y - p.y;
      const double gap2 = gx * gx + gy * gy;
      const bool same_surface =
          gap2 <= max_gap2 ||
          (gap2 <= max_collinear_gap2 && i >= 1 && i + 2 < n && finite(i - 1) && finite(i + 2) &&
           distance_to_line(q, points_in_map[i - 1], p) <= collinear_tolerance_m &&
           distance_to_line(p, points_in_map[i + 2], q) <= collinear_tolerance_m);
      if (same_surface) {
        smear_segment(p, q);
        joined = true;
      }
    }
    if (!joined) smear_segment(p, p);
  }
}

ProbabilityGrid::Sample ProbabilityGrid::interpolate(double x_m, double y_m) const {
  Sample out;
  if (cells_.empty()) return out;
  const double cx = limits_.to_cell_x(x_m);
  const double cy = limits_.to_cell_y(y_m);
  if (!std::isfinite(cx) || !std::isfinite(cy)) return out;
  const double fx = std::floor(cx);
  const double fy = std::floor(cy);
  if (fx < -3.0 || fy < -3.0 || fx > limits_.width + 2.0 || fy > limits_.height + 2.0) return out;
  const int x0 = static_cast<int>(fx);
  const int y0 = static_cast<int>(fy);
  const double tx = cx - fx;
  const double ty = cy - fy;
  // Catmull-Rom weights and their derivatives for the samples at -1, 0, 1, 2.
  auto weights = [](double t, std::array<double, 4>& w, std::array<double, 4>& dw) {
    const double t2 = t * t;
    const double t3 = t2 * t;
    w = {0.5 * (-t3 + 2.0 * t2 - t), 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0),
         0.5 * (-3.0 * t3 + 4.0 * t2 + t), 0.5 * (t3 - t2)};
    dw = {0.5 * (-3.0 * t2 + 4.0 * t - 1.0), 0.5 * (9.0 * t2 - 10.0 * t),
          0.5 * (-9.0 * t2 + 8.0 * t + 1.0), 0.5 * (3.0 * t2 - 2.0 * t)};
  };
  std::array<double, 4> wx{}, dwx{}, wy{}, dwy{};
  weights(tx, wx, dwx);
  weights(ty, wy, dwy);
  double value = 0.0, gx = 0.0, gy = 0.0;
  for (int j = 0; j < 4; ++j) {
    double row_v = 0.0, row_d = 0.0;
    for (int i = 0; i < 4; ++i) {
      const double c = at(x0 - 1 + i, y0 - 1 + j);
      row_v += wx[i] * c;
      row_d += dwx[i] * c;
    }
    value += wy[j] * row_v;
    gx += wy[j] * row_d;
    gy += dwy[j] * row_v;
  }
  const double inv_res = 1.0 / limits_.resolution_m;
  out.value = value;
  out.d_dx = gx * inv_res;
  out.d_dy = gy * inv_res;
  return out;
}

}  // namespace mobot::slam
