#include "core/slam/correlative_scan_matcher.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mobot::slam {

namespace {
constexpr int kMaxLevels = 6;
// Room beyond the window for the covariance's neighbourhood of the best candidate.
constexpr int kCovarianceMargin = 8;
}  // namespace

CorrelativeScanMatcher::CorrelativeScanMatcher(const ProbabilityGrid& grid,
                                               double max_linear_window_m)
    : limits_(grid.limits()) {
  if (!std::isfinite(max_linear_window_m) || max_linear_window_m < 0.0) {
    throw std::invalid_argument("CorrelativeScanMatcher: the window must be finite and >= 0");
  }
  if (grid.empty()) return;
  const int window_cells = static_cast<int>(std::ceil(max_linear_window_m / limits_.resolution_m));
  // The coarsest level's cells span half the window (3 x 3 first candidates per angle), up to 32
  // cells: coarser levels would cost more to build than their pruning saves.
  int level_count = 1;
  while ((1 << (level_count - 1)) < window_cells && level_count < kMaxLevels) ++level_count;
  max_window_cells_ = window_cells;
  padding_ = window_cells + kCovarianceMargin;
  padded_width_ = limits_.width + 2 * padding_;
  padded_height_ = limits_.height + 2 * padding_;
  const std::size_t size =
      static_cast<std::size_t>(padded_width_) * static_cast<std::size_t>(padded_height_);
  levels_.assign(static_cast<std::size_t>(level_count), std::vector<std::uint8_t>(size, 0));
  for (int y = 0; y < limits_.height; ++y) {
    for (int x = 0; x < limits_.width; ++x) {
      const float v = std::clamp(grid.at(x, y), 0.0F, 1.0F);
      levels_[0][static_cast<std::size_t>(y + padding_) * padded_width_ + (x + padding_)] =
          static_cast<std::uint8_t>(std::lround(v * 255.0F));
    }
  }
  // Level h from level h-1: the max of four cells 2^(h-1) apart, first along x, then along y.
  std::vector<std::uint8_t> along_x(size);
  for (int level = 1; level < level_count; ++level) {
    const auto step = static_cast<std::size_t>(1 << (level - 1));
    const std::vector<std::uint8_t>& finer = levels_[static_cast<std::size_t>(level - 1)];
    std::vector<std::uint8_t>& coarser = levels_[static_cast<std::size_t>(level)];
    const auto w = static_cast<std::size_t>(padded_width_);
    const auto h = static_cast<std::size_t>(padded_height_);
    for (std::size_t py = 0; py < h; ++py) {
      const std::uint8_t* in = &finer[py * w];
      std::uint8_t* out = &along_x[py * w];
      for (std::size_t px = 0; px < w; ++px) {
        out[px] = px + step < w ? std::max(in[px], in[px + step]) : in[px];
      }
    }
    for (std::size_t py = 0; py < h; ++py) {
      const std::uint8_t* in = &along_x[py * w];
      std::uint8_t* out = &coarser[py * w];
      if (py + step < h) {
        const std::uint8_t* above = &along_x[(py + step) * w];
        for (std::size_t px = 0; px < w; ++px) out[px] = std::max(in[px], above[px]);
      } else {
        std::copy(in, in + w, out);
      }
    }
  }
}

double CorrelativeScanMatcher::score(const DiscreteScan& scan, int level, int dx, int dy) const {
  const std::uint8_t* cells =
      levels_[static_cast<std::size_t>(level)].data() + (dy * padded_width_ + dx);
  std::uint32_t sum = 0;
  for (const std::int32_t index : scan.cells) sum += cells[index];
  return static_cast<double>(sum) / (255.0 * static_cast<double>(scan.point_count));
}

void CorrelativeScanMatcher::search(const std::vector<DiscreteScan>& scans,
                                    std::vector<Candidate> candidates, int level, int window_cells,
                                    double min_score, Candidate& best) const {
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    if (a.score != b.score) return a.score > b.score;
    if (a.scan != b.scan) return a.scan < b.scan;
    if (a.dx != b.dx) return a.dx < b.dx;
    return a.dy < b.dy;
  });
  for (const Candidate& candidate : candidates) {
    // Sorted: once a bound cannot beat the best (or the floor), none after it can.
    if (candidate.score <= best.score || candidate.score < min_score) break;
    if (level == 0) {
      best = candidate;
      break;
    }
    const int step = 1 << (level - 1);
    std::vector<Candidate> children;
    children.reserve(4);
    for (int ox : {0, step}) {
      for (int oy : {0, step}) {
        const int dx = candidate.dx + ox;
        const int dy = candidate.dy + oy;
        if (dx > window_cells || dy > window_cells) continue;
        children.push_back(
            {candidate.scan, dx, dy,
             score(scans[static_cast<std::size_t>(candidate.scan)], level - 1, dx, dy)});
      }
    }
    search(scans, std::move(children), level - 1, window_cells, min_score, best);
  }
}

std::optional<CorrelativeMatch> CorrelativeScanMatcher::match(
    std::span<const geometry::Point2D> points_in_base, const geometry::Pose2D& initial_pose,
    const CorrelativeSearchOptions& options) const {
  const bool finite = std::isfinite(options.linear_window_m) &&
                      std::isfinite(options.angular_window_rad) &&
                      std::isfinite(options.angular_step_rad) && std::isfinite(options.min_score) &&
                      std::isfinite(options.covariance_temperature);
  if (!finite || options.linear_window_m < 0.0 || options.angular_window_rad < 0.0 ||
      options.angular_step_rad < 0.0 || options.covariance_half_cells < 0 ||
      options.covariance_half_steps < 0 || !(options.covariance_temperature > 0.0)) {
    throw std::invalid_argument("CorrelativeSearchOptions: windows, steps >= 0, temperature > 0");
  }
  if (levels_.empty() || points_in_base.empty() || !geometry::is_finite(initial_pose)) {
    return std::nullopt;
  }
  const double res = limits_.resolution_m;
  double max_range_m = 0.0;
  for (const auto& p : points_in_base) max_range_m = std::max(max_range_m, std::hypot(p.x, p.y));
  double step_rad = options.angular_step_rad;
  if (step_rad <= 0.0) {
    const double r = std::max(max_range_m, res);
    step_rad = std::acos(std::max(-1.0, 1.0 - res * res / (2.0 * r * r)));
  }
  const int half_steps =
      std::min(2000, static_cast<int>(std::ceil(options.angular_window_rad / step_rad)));
  // The window in cells, capped at what the precomputed levels can bound.
  const int window_cells =
      std::min(max_window_cells_, static_cast<int>(std::ceil(options.linear_window_m / res)));

  // Rotated scans, discretised once per angle; the window's (dx, dy) then shifts whole cells.
  const int first_step = -half_steps - options.covariance_half_steps;
  const int last_step = half_steps + options.covariance_half_steps;
  std::vector<DiscreteScan> scans;
  scans.reserve(static_cast<std::size_t>(last_step - first_step + 1));
  for (int k = first_step; k <= last_step; ++k) {
    DiscreteScan scan;
    scan.angle_rad = initial_pose.theta + k * step_rad;
    const double c = std::cos(scan.angle_rad);
    const double s = std::sin(scan.angle_rad);
    scan.cells.reserve(points_in_base.size());
    scan.point_count = points_in_base.size();
    for (const auto& p : points_in_base) {
      const double x = initial_pose.x + c * p.x - s * p.y;
      const double y = initial_pose.y + s * p.x + c * p.y;
      const double cx = std::floor((x - limits_.origin_x_m) / res);
      const double cy = std::floor((y - limits_.origin_y_m) / res);
      if (!(cx >= 0.0 && cy >= 0.0 && cx < limits_.width && cy < limits_.height)) continue;
      scan.cells.push_back(static_cast<std::int32_t>(
          (static_cast<int>(cy) + padding_) * padded_width_ + static_cast<int>(cx) + padding_));
    }
    scans.push_back(std::move(scan));
  }
  const int scan_offset = -first_step;  // scans[k + scan_offset] is angular step k

  const int top = levels() - 1;
  const int top_step = 1 << top;
  std::vector<Candidate> candidates;
  for (int k = -half_steps; k <= half_steps; ++k) {
    const int index = k + scan_offset;
    for (int dx = -window_cells; dx <= window_cells; dx += top_step) {
      for (int dy = -window_cells; dy <= window_cells; dy += top_step) {
        candidates.push_back(
            {index, dx, dy, score(scans[static_cast<std::size_t>(index)], top, dx, dy)});
      }
    }
  }
  Candidate best{-1, 0, 0, -1.0};
  search(scans, std::move(candidates), top, window_cells, options.min_score, best);
  if (best.scan < 0 || best.score < options.min_score) return std::nullopt;

  CorrelativeMatch out;
  out.score = best.score;
  out.pose = {initial_pose.x + best.dx * res, initial_pose.y + best.dy * res,
              geometry::wrap_angle(scans[static_cast<std::size_t>(best.scan)].angle_rad)};

  // Response around the best, as a distribution over the offsets (Olson's covariance).
  const int hc = std::min(options.covariance_half_cells, kCovarianceMargin);
  const int hs = options.covariance_half_steps;
  double weight_sum = 0.0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (int k = -hs; k <= hs; ++k) {
    const int index = best.scan + k;
    if (index < 0 || index >= static_cast<int>(scans.size())) continue;
    for (int dx = -hc; dx <= hc; ++dx) {
      for (int dy = -hc; dy <= hc; ++dy) {
        const double s =
            score(scans[static_cast<std::size_t>(index)], 0, best.dx + dx, best.dy + dy);
        const double w = std::exp(-(best.score - s) / options.covariance_temperature);
        const Eigen::Vector3d d(dx * res, dy * res, k * step_rad);
        weight_sum += w;
        mean += w * d;
        second += w * d * d.transpose();
      }
    }
  }
  mean /= weight_sum;
  out.covariance = second / weight_sum - mean * mean.transpose();
  const double floor_xy = 0.25 * res * 0.25 * res;
  const double floor_theta = 0.25 * step_rad * 0.25 * step_rad;
  out.covariance(0, 0) += floor_xy;
  out.covariance(1, 1) += floor_xy;
  out.covariance(2, 2) += floor_theta;
  return out;
}

}  // namespace mobot::slam
