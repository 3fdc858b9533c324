#include "core/safety/ir_safety.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace mobot::safety {
namespace {

// A sensor's bearing counts as left or right of the base's axis beyond this (the sensors at 0 and
// 180 degrees are on neither side).
constexpr double kSideSine = 1e-6;

// The obstacle point of a reading in the base frame, when the reading shows one.
std::optional<geometry::Point2D> obstacle_point(const msgs::RangeReading& reading) {
  const geometry::Pose2D& mount = reading.sensor_in_base;
  if (!geometry::is_finite(mount) || !std::isfinite(reading.range_m) || reading.range_m < 0.0 ||
      !(reading.range_m < reading.range_max_m)) {
    return std::nullopt;
  }
  return geometry::transform_point(mount, {reading.range_m, 0.0});
}

// The speed at which the base closes on a point of its own frame: only the linear velocity moves
// the centre (a round base turning on the spot closes on nothing), projected onto the point.
double approach_mps(geometry::Point2D point, double forward_mps, double reverse_mps) {
  const double distance_m = std::hypot(point.x, point.y);
  if (distance_m <= 0.0) return std::max(forward_mps, reverse_mps);
  if (point.x > 0.0) return forward_mps * point.x / distance_m;
  if (point.x < 0.0) return reverse_mps * -point.x / distance_m;
  return 0.0;
}

void check(const IrSafetyOptions& options) {
  for (const double value :
       {options.urgent_radius_m, options.urgent_clear_margin_m, options.moving_speed_mps,
        options.stopped_speed_mps, options.stop_max_s, options.back_off_speed_mps,
        options.back_off_distance_m, options.back_off_max_s, options.bubble_gain,
        options.bubble_period_s, options.bubble_max_m, options.turn_rate_radps, options.turn_max_s,
        options.max_ring_age_s}) {
    if (!std::isfinite(value) || value < 0.0) {
      throw std::invalid_argument("ir safety: distances, speeds, gains and times must be >= 0");
    }
  }
  for (const double gain : options.bubble_gains) {
    if (!std::isfinite(gain) || gain < 0.0) {
      throw std::invalid_argument("ir safety: bubble gains must be >= 0");
    }
  }
  if (options.confirm_rings < 1) {
    throw std::invalid_argument("ir safety: confirm_rings must be at least 1");
  }
}

}  // namespace

std::string_view to_string(IrZone zone) { return zone == IrZone::kUrgent ? "urgent" : "bubble"; }

std::string_view to_string(IrReaction reaction) {
  switch (reaction) {
    case IrReaction::kStop:
      return "stop";
    case IrReaction::kBackOff:
      return "back_off";
    case IrReaction::kTurnLeft:
      return "turn_left";
    case IrReaction::kTurnRight:
      return "turn_right";
  }
  return "stop";
}

IrSafety::IrSafety(IrSafetyOptions options) : options_(std::move(options)) { check(options_); }

void IrSafety::reset() {
  ring_.reset();
  urgent_rings_ = 0;
  bubble_rings_ = 0;
  phase_ = Phase::kIdle;
  stepped_ = false;
}

double IrSafety::bubble_m(const msgs::RangeReading& reading, std::size_t index, double forward_mps,
                          double reverse_mps) const {
  const double along = std::cos(reading.sensor_in_base.theta);
  if (!std::isfinite(along)) return 0.0;
  const double speed_mps = along > 0.0 ? forward_mps * along : reverse_mps * -along;
  const double gain =
      index < options_.bubble_gains.size() ? options_.bubble_gains[index] : options_.bubble_gain;
  return std::min(gain * speed_mps * options_.bubble_period_s, options_.bubble_max_m);
}

std::optional<IrSafety::Hit> IrSafety::urgent_hit(const msgs::IrRing& ring,
                                                  const BaseMotion& motion) const {
  std::optional<Hit> nearest;
  for (std::size_t i = 0; i < ring.readings.size(); ++i) {
    const std::optional<geometry::Point2D> point = obstacle_point(ring.readings[i]);
    if (!point) continue;
    const double distance_m = std::hypot(point->x, point->y);
    if (distance_m > options_.urgent_radius_m) continue;
    if (approach_mps(*point, motion.forward_mps(), motion.reverse_mps()) <=
        options_.moving_speed_mps) {
      continue;
    }
    if (!nearest || distance_m < nearest->distance_m) {
      nearest = Hit{i, ring.readings[i].range_m, distance_m, point->x >= 0.0};
    }
  }
  return nearest;
}

std::vector<std::size_t> IrSafety::bubble_hits(const msgs::IrRing& ring, double forward_mps,
                                               double reverse_mps) const {
  std::vector<std::size_t> hits;
  for (std::size_t i = 0; i < ring.readings.size(); ++i) {
    const msgs::RangeReading& reading = ring.readings[i];
    if (!obstacle_point(reading)) continue;
    if (reading.range_m < bubble_m(reading, i, forward_mps, reverse_mps)) hits.push_back(i);
  }
  return hits;
}

bool IrSafety::side_occupied(const msgs::IrRing& ring, bool ahead, double radius_m) const {
  return std::any_of(ring.readings.begin(), ring.readings.end(), [&](const auto& reading) {
    const std::optional<geometry::Point2D> point = obstacle_point(reading);
    if (!point || (ahead ? point->x <= 0.0 : point->x >= 0.0)) return false;
    return std::hypot(point->x, point->y) <= radius_m;
  });
}

std::optional<IrSafetyDecision> IrSafety::step(const std::optional<msgs::IrRing>& new_ring,
                                               const BaseMotion& motion, double now_s) {
  const double dt_s = stepped_ ? std::max(0.0, now_s - last_step_s_) : 0.0;
  last_step_s_ = now_s;
  stepped_ = true;
  if (new_ring) {
    ring_ = *new_ring;
    ring_s_ = now_s;
  }
  const bool fresh = ring_ && now_s - ring_s_ <= options_.max_ring_age_s;
  if (!fresh) {
    urgent_rings_ = 0;
    bubble_rings_ = 0;
  }

  std::optional<Hit> urgent;
  std::vector<std::size_t> bubble;
  if (new_ring && fresh) {
    urgent = urgent_hit(*ring_, motion);
    bubble = bubble_hits(*ring_, motion.forward_mps(), motion.reverse_mps());
    urgent_rings_ = urgent ? urgent_rings_ + 1 : 0;
    bubble_rings_ = bubble.empty() ? 0 : bubble_rings_ + 1;
  }

  if (phase_ == Phase::kIdle) {
    if (urgent && urgent_rings_ >= options_.confirm_rings) {
      start_urgent(*urgent, now_s);
    } else if (!bubble.empty() && bubble_rings_ >= options_.confirm_rings) {
      start_bubble(*ring_, bubble, motion, now_s);
    }
    return decision();
  }

  // Only the measured motion moves the base back; integrate it between ticks.
  if (phase_ == Phase::kBackingOff) {
    const double measured_mps =
        std::isfinite(motion.measured.linear_mps) ? std::abs(motion.measured.linear_mps) : 0.0;
    backed_off_m_ += measured_mps * dt_s;
  }
  advance(motion, now_s, new_ring.has_value() && fresh);
  return decision();
}

void IrSafety::start_urgent(const Hit& hit, double now_s) {
  active_ = {IrZone::kUrgent, IrReaction::kStop, hit.sensor, hit.range_m, true, {}};
  obstacle_ahead_ = hit.ahead;
  enter(Phase::kStopping, now_s);
}

void IrSafety::start_bubble(const msgs::IrRing& ring, const std::vector<std::size_t>& hits,
                            const BaseMotion& motion, double now_s) {
  entry_forward_mps_ = motion.forward_mps();
  entry_reverse_mps_ = motion.reverse_mps();
  const bool reversing = entry_reverse_mps_ > entry_forward_mps_;
  int left = 0;
  int right = 0;
  std::size_t nearest = hits.front();
  for (const std::size_t i : hits) {
    const double side = std::sin(ring.readings[i].sensor_in_base.theta);
    left += side > kSideSine ? 1 : 0;
    right += side < -kSideSine ? 1 : 0;
    if (ring.readings[i].range_m < ring.readings[nearest].range_m) nearest = i;
  }
  // Turning left swings the front to the left and the rear to the right: going forward the base
  // turns away from the side with more hits, reversing toward it.
  bool turn_left = false;
  if (left != right) {
    turn_left = (right > left) != reversing;
  } else {
    // As many hits on each side (often one, dead ahead): toward the side with more room.
    double left_clear_m = std::numeric_limits<double>::infinity();
    double right_clear_m = std::numeric_limits<double>::infinity();
    for (const auto& reading : ring.readings) {
      if (!std::isfinite(reading.range_m) || reading.range_m < 0.0) continue;
      const double side = std::sin(reading.sensor_in_base.theta);
      if (side > kSideSine) left_clear_m = std::min(left_clear_m, reading.range_m);
      if (side < -kSideSine) right_clear_m = std::min(right_clear_m, reading.range_m);
    }
    const bool left_roomier = left_clear_m >= right_clear_m;
    turn_left = left_roomier != reversing;
  }
  active_ = {
      IrZone::kBubble, turn_left ? IrReaction::kTurnLeft : IrReaction::kTurnRight,
      nearest,         ring.readings[nearest].range_m,
      false,           {0.0, turn_left ? options_.turn_rate_radps : -options_.turn_rate_radps}};
  enter(Phase::kTurning, now_s);
}

void IrSafety::advance(const BaseMotion& motion, double now_s, bool new_ring) {
  const double in_phase_s = now_s - phase_start_s_;
  const bool fresh = ring_ && now_s - ring_s_ <= options_.max_ring_age_s;
  switch (phase_) {
    case Phase::kIdle:
      return;
    case Phase::kStopping: {
      const bool stopped = std::isfinite(motion.measured.linear_mps) &&
                           std::abs(motion.measured.linear_mps) < options_.stopped_speed_mps;
      if (!stopped && in_phase_s < options_.stop_max_s) return;
      // Backing off must not hit what may be behind: the whole back-off distance must be clear.
      const bool blocked =
          fresh && side_occupied(*ring_, !obstacle_ahead_,
                                 options_.urgent_radius_m + options_.back_off_distance_m);
      if (blocked || options_.back_off_distance_m <= 0.0) {
        enter(Phase::kIdle, now_s);
        return;
      }
      backed_off_m_ = 0.0;
      active_.reaction = IrReaction::kBackOff;
      active_.command = {
          obstacle_ahead_ ? -options_.back_off_speed_mps : options_.back_off_speed_mps, 0.0};
      enter(Phase::kBackingOff, now_s);
      return;
    }
    case Phase::kBackingOff: {
      const bool far_enough = backed_off_m_ >= options_.back_off_distance_m;
      const bool cleared =
          new_ring && !side_occupied(*ring_, obstacle_ahead_,
                                     options_.urgent_radius_m + options_.urgent_clear_margin_m);
      const bool behind =
          fresh && side_occupied(*ring_, !obstacle_ahead_, options_.urgent_radius_m);
      if (far_enough || cleared || behind || in_phase_s >= options_.back_off_max_s) {
        enter(Phase::kIdle, now_s);
      }
      return;
    }
    case Phase::kTurning: {
      const bool clear =
          new_ring && bubble_hits(*ring_, entry_forward_mps_, entry_reverse_mps_).empty();
      if (clear || !fresh || in_phase_s >= options_.turn_max_s) enter(Phase::kIdle, now_s);
      return;
    }
  }
}

void IrSafety::enter(Phase phase, double now_s) {
  phase_ = phase;
  phase_start_s_ = now_s;
  if (phase == Phase::kIdle) {
    // A new reaction needs its own confirmation.
    urgent_rings_ = 0;
    bubble_rings_ = 0;
  }
}

std::optional<IrSafetyDecision> IrSafety::decision() const {
  if (phase_ == Phase::kIdle) return std::nullopt;
  return active_;
}

}  // namespace mobot::safety
