#include "drivers/sim/moving_target.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace mobot::sim {
namespace {

[[noreturn]] void reject(const std::string& field, const std::string& rule, double value) {
  std::ostringstream message;
  message << "moving target: " << field << " must be " << rule << " (got " << value << ")";
  throw std::invalid_argument(message.str());
}

void check_spec(const MovingTargetSpec& spec) {
  if (!std::isfinite(spec.radius_m) || spec.radius_m <= 0.0) {
    reject("radius_m", "finite and > 0", spec.radius_m);
  }
  if (!std::isfinite(spec.height_m) || spec.height_m < 0.0) {
    reject("height_m", "finite and >= 0", spec.height_m);
  }
  if (!std::isfinite(spec.speed_mps) || spec.speed_mps < 0.0) {
    reject("speed_mps", "finite and >= 0", spec.speed_mps);
  }
  if (spec.path.empty()) {
    throw std::invalid_argument("moving target: path must have at least one point");
  }
  for (std::size_t i = 0; i < spec.path.size(); ++i) {
    const geometry::Point2D& point = spec.path[i];
    if (!std::isfinite(point.x) || !std::isfinite(point.y)) {
      reject("path[" + std::to_string(i) + "]", "finite",
             std::isfinite(point.x) ? point.y : point.x);
    }
  }
}

}  // namespace

MovingTarget::MovingTarget(MovingTargetSpec spec) : spec_(std::move(spec)) {
  check_spec(spec_);
  const std::size_t vertices = spec_.path.size() + (spec_.loop ? 1 : 0);
  cumulative_m_.assign(1, 0.0);
  for (std::size_t i = 1; i < vertices; ++i) {
    const geometry::Point2D& a = vertex(i - 1);
    const geometry::Point2D& b = vertex(i);
    cumulative_m_.push_back(cumulative_m_.back() + std::hypot(b.x - a.x, b.y - a.y));
  }
}

const geometry::Point2D& MovingTarget::vertex(std::size_t i) const {
  return spec_.path[i % spec_.path.size()];
}

geometry::Point2D MovingTarget::position_at(double time_s) const {
  if (!std::isfinite(time_s)) reject("time_s", "finite", time_s);
  const double length_m = path_length_m();
  if (length_m <= 0.0 || time_s <= 0.0) return spec_.path.front();
  const double travelled_m = spec_.speed_mps * time_s;
  return point_at_distance(spec_.loop ? std::fmod(travelled_m, length_m)
                                      : std::min(travelled_m, length_m));
}

geometry::Point2D MovingTarget::point_at_distance(double distance_m) const {
  // The segment [i - 1, i] holding the distance; zero-length segments are skipped by upper_bound.
  const auto after = std::upper_bound(cumulative_m_.begin(), cumulative_m_.end(), distance_m);
  if (after == cumulative_m_.end()) return vertex(cumulative_m_.size() - 1);
  const auto i = static_cast<std::size_t>(after - cumulative_m_.begin());
  const double start_m = cumulative_m_[i - 1];
  const double fraction = (distance_m - start_m) / (cumulative_m_[i] - start_m);
  const geometry::Point2D& a = vertex(i - 1);
  const geometry::Point2D& b = vertex(i);
  return {a.x + fraction * (b.x - a.x), a.y + fraction * (b.y - a.y)};
}

}  // namespace mobot::sim
