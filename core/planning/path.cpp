#include "core/planning/path.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mobot::planning {

double distance(geometry::Point2D a, geometry::Point2D b) {
  return std::hypot(b.x - a.x, b.y - a.y);
}

Path::Path(std::vector<geometry::Point2D> points_in_map) {
  points_.reserve(points_in_map.size());
  cumulative_m_.reserve(points_in_map.size());
  for (const auto& point : points_in_map) {
    if (!points_.empty() && points_.back() == point) continue;
    cumulative_m_.push_back(
        points_.empty() ? 0.0 : cumulative_m_.back() + distance(points_.back(), point));
    points_.push_back(point);
  }
}

bool Path::all_finite() const {
  return std::all_of(points_.begin(), points_.end(), [](const geometry::Point2D& p) {
    return std::isfinite(p.x) && std::isfinite(p.y);
  });
}

std::size_t Path::segment_at(double s_m) const {
  // The segment i spans [cumulative_m_[i], cumulative_m_[i + 1]].
  const auto it = std::upper_bound(cumulative_m_.begin(), cumulative_m_.end(), s_m);
  const auto after = static_cast<std::size_t>(it - cumulative_m_.begin());
  const std::size_t last_segment = points_.size() - 2;
  return after == 0 ? 0 : std::min(after - 1, last_segment);
}

geometry::Point2D Path::point_at(double s_m) const {
  if (points_.size() == 1 || s_m <= 0.0) return points_.front();
  if (s_m >= length_m()) return points_.back();
  const std::size_t i = segment_at(s_m);
  const double span = cumulative_m_[i + 1] - cumulative_m_[i];
  const double t = (s_m - cumulative_m_[i]) / span;
  const auto& a = points_[i];
  const auto& b = points_[i + 1];
  return {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
}

double Path::heading_at(double s_m) const {
  if (points_.size() < 2) return 0.0;
  const std::size_t i = segment_at(std::clamp(s_m, 0.0, length_m()));
  return std::atan2(points_[i + 1].y - points_[i].y, points_[i + 1].x - points_[i].x);
}

double Path::project(geometry::Point2D point, double from_s_m, double window_m) const {
  if (points_.size() < 2) return 0.0;
  const double lo = std::clamp(from_s_m, 0.0, length_m());
  const double hi = std::clamp(from_s_m + window_m, lo, length_m());
  double best_s = lo;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = segment_at(lo); i + 1 < points_.size() && cumulative_m_[i] <= hi; ++i) {
    const auto& a = points_[i];
    const auto& b = points_[i + 1];
    const double span = cumulative_m_[i + 1] - cumulative_m_[i];
    const double t =
        ((point.x - a.x) * (b.x - a.x) + (point.y - a.y) * (b.y - a.y)) / (span * span);
    const double s = std::clamp(cumulative_m_[i] + std::clamp(t, 0.0, 1.0) * span, lo, hi);
    const geometry::Point2D q = point_at(s);
    const double d2 = (q.x - point.x) * (q.x - point.x) + (q.y - point.y) * (q.y - point.y);
    if (d2 < best_d2) {
      best_d2 = d2;
      best_s = s;
    }
  }
  return best_s;
}

}  // namespace mobot::planning
