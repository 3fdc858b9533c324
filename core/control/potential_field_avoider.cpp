#include "core/control/potential_field_avoider.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/numeric/finite.h"

namespace mobot::control {

PotentialFieldAvoider::PotentialFieldAvoider(const PotentialFieldOptions& options)
    : options_(options) {
  if (!finite_positive(options.influence_distance_m) || !finite_positive(options.k_att) ||
      !finite_positive(options.k_rep) || !finite_positive(options.sector_half_angle_rad) ||
      !std::isfinite(options.steer_offset_rad) || !finite_positive(options.max_linear_mps) ||
      !finite_positive(options.max_angular_radps) || !(options.side_hysteresis >= 0.0)) {
    throw std::invalid_argument("potential field options out of range");
  }
}

std::optional<SonarObstacle> PotentialFieldAvoider::to_obstacle(const msgs::RangeReading& reading) {
  const double range = reading.range_m;
  if (!std::isfinite(range) || !geometry::is_finite(reading.sensor_in_base) ||
      range < reading.range_min_m || range >= reading.range_max_m || range <= 0.0) {
    return std::nullopt;
  }
  const geometry::Point2D echo =
      geometry::transform_point(reading.sensor_in_base, geometry::Point2D{range, 0.0});
  return SonarObstacle{range, std::atan2(echo.y, echo.x)};
}

bool PotentialFieldAvoider::in_sector(const SonarObstacle& obstacle) const {
  return std::abs(obstacle.bearing_rad) <= options_.sector_half_angle_rad;
}

double PotentialFieldAvoider::repulsion(double range_m) const {
  if (range_m >= options_.influence_distance_m) return 0.0;
  return options_.k_rep * (1.0 / range_m - 1.0 / options_.influence_distance_m) /
         (range_m * range_m);
}

std::optional<SonarObstacle> PotentialFieldAvoider::nearest_in_sector(
    std::span<const msgs::RangeReading> readings) const {
  std::optional<SonarObstacle> nearest;
  for (const auto& reading : readings) {
    const auto obstacle = to_obstacle(reading);
    if (!obstacle || !in_sector(*obstacle)) continue;
    if (!nearest || obstacle->range_m < nearest->range_m) nearest = obstacle;
  }
  return nearest;
}

bool PotentialFieldAvoider::is_active(std::span<const msgs::RangeReading> readings) const {
  const auto nearest = nearest_in_sector(readings);
  return nearest && nearest->range_m < options_.influence_distance_m;
}

int PotentialFieldAvoider::choose_side(double left, double right) {
  const double total = left + right;
  if (total <= 0.0) return 0;
  const bool balanced = std::abs(left - right) < options_.side_hysteresis * total;
  if (!(balanced && last_side_ != 0)) last_side_ = left >= right ? 1 : -1;
  return last_side_;
}

PotentialFieldAvoider::Output PotentialFieldAvoider::compute(
    const geometry::Pose2D& pose, const geometry::Point2D& goal_in_map,
    std::span<const msgs::RangeReading> readings) {
  Output out;
  if (!geometry::is_finite(pose) || !std::isfinite(goal_in_map.x) ||
      !std::isfinite(goal_in_map.y)) {
    return out;
  }
  const double c = std::cos(pose.theta);
  const double s = std::sin(pose.theta);
  out.v_attractive_mps =
      -options_.k_att * ((pose.x - goal_in_map.x) * c + (pose.y - goal_in_map.y) * s);

  // Left/right split by the sign of the bearing; the echo's weight is its repulsion magnitude.
  double left = 0.0;
  double right = 0.0;
  for (const auto& reading : readings) {
    const auto obstacle = to_obstacle(reading);
    if (!obstacle || !in_sector(*obstacle)) continue;
    const double magnitude = repulsion(obstacle->range_m);
    out.v_repulsive_mps += magnitude * std::cos(obstacle->bearing_rad);
    (obstacle->bearing_rad >= 0.0 ? left : right) += magnitude;
  }
  out.obstacle_side = choose_side(left, right);

  const double goal_bearing = std::atan2(goal_in_map.y - pose.y, goal_in_map.x - pose.x);
  out.steer_heading_rad =
      geometry::wrap_angle(goal_bearing - out.obstacle_side * options_.steer_offset_rad);
  const double w = -options_.k_att * geometry::wrap_angle(pose.theta - out.steer_heading_rad);
  const double v = out.v_attractive_mps - out.v_repulsive_mps;
  const double min_v = options_.allow_reverse ? -options_.max_linear_mps : 0.0;
  out.command = {std::clamp(v, min_v, options_.max_linear_mps),
                 std::clamp(w, -options_.max_angular_radps, options_.max_angular_radps)};
  return out;
}

}  // namespace mobot::control
