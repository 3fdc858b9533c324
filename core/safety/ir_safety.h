#pragma once

#include <cstddef>
#include <optional>
#include <string_view>
#include <vector>

#include "core/msgs/ir_ring.h"
#include "core/msgs/twist.h"
#include "core/safety/base_motion.h"

namespace mobot::safety {

// docs/algorithms.md C6, the two reactive layers on the infrared ring. Defaults: the Dashgo D1
// (a round base of radius 0.20 m, ten Sharp sensors read at 20 Hz, R2).
struct IrSafetyOptions {
  // Urgent zone U: an obstacle point closer than this to the base centre (C6: 0.20-0.30 m; the
  // body ends at 0.20 m, so U is the 10 cm in front of it).
  double urgent_radius_m = 0.30;
  // The back-off ends early once no obstacle point on that side is within urgent_radius_m plus
  // this: the readings jitter by a centimetre or two.
  double urgent_clear_margin_m = 0.05;
  // Approaching an obstacle point slower than this is not moving toward it.
  double moving_speed_mps = 0.02;
  // The stop holds until the measured speed is under stopped_speed_mps, at most stop_max_s, then
  // the base backs off at back_off_speed_mps for at most back_off_distance_m (measured), or
  // back_off_max_s when the odometry shows no progress.
  double stopped_speed_mps = 0.01;
  double stop_max_s = 0.5;
  double back_off_speed_mps = 0.10;
  double back_off_distance_m = 0.10;
  double back_off_max_s = 2.0;
  // Reactive bubble B: sensor i's reading is inside when shorter than
  // bb_i = min(K_i * V_i * dt, bubble_max_m), V_i the base's speed along the sensor's bearing
  // (0 for a sensor facing away from the motion). bubble_gains holds K_i per sensor; sensors
  // beyond its end use bubble_gain. With 24 and the ring's 0.05 s period the bubble reaches
  // 0.6 m ahead at the Dashgo's 0.5 m/s, about the distance the planner needs to swerve.
  std::vector<double> bubble_gains;
  double bubble_gain = 24.0;
  double bubble_period_s = 0.05;
  double bubble_max_m = 0.70;
  // The turn away from the bubble's hits, on the spot, until no reading is inside the bubble the
  // base had when it started (or turn_max_s: about 90 degrees).
  double turn_rate_radps = 0.4;
  double turn_max_s = 4.0;
  // New rings in a row that must show an obstacle before a reaction starts: a Sharp sensor
  // spikes now and then (a reading taken during its LED pulse reads near).
  int confirm_rings = 2;
  // A ring older than this is not used (its silence is the sensor watchdog's business).
  double max_ring_age_s = 0.25;
};

enum class IrZone { kUrgent, kBubble };
enum class IrReaction { kStop, kBackOff, kTurnLeft, kTurnRight };

std::string_view to_string(IrZone zone);          // "urgent" | "bubble"
std::string_view to_string(IrReaction reaction);  // "stop" | "back_off" | "turn_left" | ...

struct IrSafetyDecision {
  IrZone zone = IrZone::kUrgent;
  IrReaction reaction = IrReaction::kStop;
  std::size_t sensor = 0;  // the ring's reading that started the reaction
  double range_m = 0.0;    // its reading then
  bool alarm = false;      // the urgent zone: the operator must hear about it
  msgs::Twist command;     // for the "ir_safety" mux source
};

// The state of the reactions between ticks: the urgent zone stops, then backs off away from the
// obstacle; the bubble turns away from the side with more hits. Deterministic; time is an
// argument. Call step() every control tick, with the ring only on the ticks a new one arrived.
class IrSafety {
 public:
  // Throws std::invalid_argument for negative or non-finite options or a zero confirm_rings.
  explicit IrSafety(IrSafetyOptions options = {});

  // The command the ir_safety source must give this tick, or nothing when no reaction runs (the
  // source should fall silent at once). A reading that is not finite, negative, beyond its
  // range_max_m, or from a mount that is not finite is ignored; range_max_m itself means nothing
  // in range. A base that neither moves nor is told to move starts nothing.
  std::optional<IrSafetyDecision> step(const std::optional<msgs::IrRing>& new_ring,
                                       const BaseMotion& motion, double now_s);

  // Forgets the running reaction and the confirmations (e-stop, reset).
  void reset();

  // Sensor i's bubble at this motion (bb_i of C6), for tests and the dashboard.
  double bubble_m(const msgs::RangeReading& reading, std::size_t index, double forward_mps,
                  double reverse_mps) const;

  const IrSafetyOptions& options() const { return options_; }

 private:
  enum class Phase { kIdle, kStopping, kBackingOff, kTurning };
  struct Hit {
    std::size_t sensor = 0;
    double range_m = 0.0;
    double distance_m = 0.0;  // of the obstacle point from the base centre
    bool ahead = true;        // the point lies in front of the axle
  };

  std::optional<Hit> urgent_hit(const msgs::IrRing& ring, const BaseMotion& motion) const;
  std::vector<std::size_t> bubble_hits(const msgs::IrRing& ring, double forward_mps,
                                       double reverse_mps) const;
  // Whether a usable obstacle point on the given side lies within `radius_m` of the centre.
  bool side_occupied(const msgs::IrRing& ring, bool ahead, double radius_m) const;
  void start_urgent(const Hit& hit, double now_s);
  void start_bubble(const msgs::IrRing& ring, const std::vector<std::size_t>& hits,
                    const BaseMotion& motion, double now_s);
  void advance(const BaseMotion& motion, double now_s, bool new_ring);
  void enter(Phase phase, double now_s);
  std::optional<IrSafetyDecision> decision() const;

  IrSafetyOptions options_;
  std::optional<msgs::IrRing> ring_;
  double ring_s_ = 0.0;
  int urgent_rings_ = 0;  // consecutive new rings with an urgent hit
  int bubble_rings_ = 0;
  Phase phase_ = Phase::kIdle;
  double phase_start_s_ = 0.0;
  double last_step_s_ = 0.0;
  bool stepped_ = false;
  IrSafetyDecision active_;
  bool obstacle_ahead_ = true;  // urgent: which side the obstacle is on
  double backed_off_m_ = 0.0;
  double entry_forward_mps_ = 0.0;  // bubble: the motion the bubble was measured with
  double entry_reverse_mps_ = 0.0;
};

}  // namespace mobot::safety
