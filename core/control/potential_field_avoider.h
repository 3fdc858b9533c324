#pragma once

#include <numbers>
#include <optional>
#include <span>

#include "core/geometry/pose2d.h"
#include "core/msgs/sonar_ring.h"
#include "core/msgs/twist.h"

namespace mobot::control {

struct PotentialFieldOptions {
  double influence_distance_m = 0.7;  // d0: echoes nearer than this repel
  double k_att = 10.0;
  double k_rep = 10.0;
  // Only echoes within this angle of the heading count (seen from the robot centre).
  double sector_half_angle_rad = std::numbers::pi / 3.0;
  // With an obstacle in the sector the robot steers this far from the goal bearing, away from it.
  double steer_offset_rad = std::numbers::pi / 3.0;
  // Robot limits. The linear cap is the speed used while avoiding (chosen: R1's fastest tested
  // speed, 0.45 m/s; the attractive term alone would command v_max right up to the obstacle).
  double max_linear_mps = 0.45;
  double max_angular_radps = 2.0;
  // false: the repulsion can stop the robot but not back it up (the ring sees little behind it).
  bool allow_reverse = false;
  // When left and right repulsion differ by less than this fraction, keep the side chosen before,
  // so an obstacle dead ahead does not flip the escape direction on every echo.
  double side_hysteresis = 0.2;
};

// One echo turned into an obstacle seen from the robot centre, in the base frame.
struct SonarObstacle {
  double range_m = 0.0;      // d_i: the reading itself, the distance from the sensor (the body)
  double bearing_rad = 0.0;  // of the echo point from the robot centre, relative to the heading
};

// docs/algorithms.md C4: potential-field avoidance with the sonar ring, used by the navigation loop
// in place of the path tracker while an obstacle is within d0 in front of the robot. Attractive:
// v_att = -k_att [(x - xg) cos th + (y - yg) sin th], w = -k_att (th - th_steer). Repulsive, per
// echo at d_i < d0 within the sector: k_rep (1/d_i - 1/d0) / d_i^2 away from the echo; its
// component along the heading slows (or stops) the robot. th_steer is the goal bearing, or with
// obstacles in the sector the goal bearing +/- steer_offset_rad away from the side holding more
// repulsion. Everything is clamped to the limits.
class PotentialFieldAvoider {
 public:
  struct Output {
    msgs::Twist command;
    double v_attractive_mps = 0.0;
    double v_repulsive_mps = 0.0;  // along the heading, positive = pushes backwards
    double steer_heading_rad = 0.0;
    int obstacle_side = 0;  // +1 obstacle on the left, -1 on the right, 0 none in the sector
  };

  // Throws std::invalid_argument on non-positive distances, gains or limits.
  explicit PotentialFieldAvoider(const PotentialFieldOptions& options = {});

  const PotentialFieldOptions& options() const { return options_; }

  // The echo as an obstacle, or nothing for "no echo" (range at or beyond range_max), a range
  // below range_min or a non-finite reading.
  static std::optional<SonarObstacle> to_obstacle(const msgs::RangeReading& reading);
  // True when some echo is nearer than d0 within the sector: the loop should avoid.
  bool is_active(std::span<const msgs::RangeReading> readings) const;
  // The nearest valid echo in the sector, if any.
  std::optional<SonarObstacle> nearest_in_sector(
      std::span<const msgs::RangeReading> readings) const;

  // Steers toward goal_in_map. A non-finite pose or goal gives a zero command.
  Output compute(const geometry::Pose2D& pose, const geometry::Point2D& goal_in_map,
                 std::span<const msgs::RangeReading> readings);
  // Forgets the latched escape side (new obstacle encounter).
  void reset() { last_side_ = 0; }

 private:
  bool in_sector(const SonarObstacle& obstacle) const;
  double repulsion(double range_m) const;
  int choose_side(double left, double right);

  PotentialFieldOptions options_;
  int last_side_ = 0;
};

}  // namespace mobot::control
