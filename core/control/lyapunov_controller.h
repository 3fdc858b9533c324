#pragma once

#include <limits>
#include <optional>

#include "core/geometry/pose2d.h"
#include "core/msgs/twist.h"

namespace mobot::control {

struct LyapunovGains {
  double k_v = 1.0;      // speed gain: v = k_v rho cos(alpha)
  double k_alpha = 2.0;  // turn-toward-the-goal gain
  double k_theta = 1.0;  // heading gain of the local law
  double h = 5.0;        // weight of the approach-direction error phi
};

struct LyapunovOptions {
  LyapunovGains gains;
  // Radius of the local configuration set: inside it the local law (w = -k_theta th_e) replaces
  // the global one. C2 needs eps_rho > |e_rho|max + e_v,max / k_v (see min_eps_rho); with the C2
  // bounds that is 0.1414 + 0.065 = 0.2064 m, so 0.21 m.
  double eps_rho_m = 0.21;
  // The local law is left again only when rho exceeds factor * eps_rho_m: without this margin a
  // noisy rho near eps_rho would chatter between the laws.
  double local_exit_factor = 2.0;
  // Also require the offset from the goal's heading line, |rho sin(phi)|, below this to enter the
  // local law (left again above factor times it). The local law only turns to the goal heading and
  // drives along it, so an offset present on entry is never removed; a tracker that must arrive
  // within a tolerance sets this below the tolerance. Infinite (off) reproduces C2 exactly.
  double local_entry_max_lateral_m = std::numeric_limits<double>::infinity();
  // false: the global law everywhere (C2's baseline, unstable near the goal under noise).
  bool two_law = true;
  // C2: when the goal lies behind (|alpha| > pi/2) drive backwards. The law then runs in the frame
  // of the robot's rear (theta + pi, so alpha and phi shift by pi) and v is negated; the robot
  // reaches the goal reversing with the requested heading instead of turning around first. The
  // direction is latched and changes only when |alpha| crosses pi/2 by reverse_hysteresis_rad.
  // false: forward only (v >= 0; the robot turns on the spot toward a goal behind it).
  bool allow_reverse = true;
  double reverse_hysteresis_rad = 0.2;
  double max_linear_mps = 1.3;  // R1 v_max
  double max_angular_radps = 2.0;
};

// The smallest eps_rho C2's stability argument allows: |e_rho|max + e_v,max / k_v.
double min_eps_rho(double max_rho_error_m, double max_speed_error_mps, double k_v);

// C2's polar error coordinates of a pose relative to a goal (all angles wrapped to (-pi, pi]).
struct PolarError {
  double rho_m = 0.0;              // distance to the goal
  double alpha_rad = 0.0;          // bearing of the goal relative to the robot's heading
  double phi_rad = 0.0;            // bearing of the goal relative to the goal's heading
  double heading_error_rad = 0.0;  // th_e = th - th_g
  double lateral_m() const;        // offset from the goal's heading line, |rho sin(phi)|
};

PolarError polar_error(const geometry::Pose2D& pose, const geometry::Pose2D& goal);

enum class LyapunovLaw { kGlobal, kLocal };

// docs/algorithms.md C2: Lyapunov point stabilisation of a unicycle to a goal pose.
// Global law: v = k_v rho cos(alpha), w = k_alpha alpha + k_v (sin(alpha) cos(alpha) / alpha)
// (alpha + h phi). Local law (rho < eps_rho): v = k_v rho cos(alpha), w = -k_theta th_e.
// Both outputs are clamped to the speed limits. The instance latches the active law and the
// driving direction, so call reset() when the goal changes.
class LyapunovController {
 public:
  struct Output {
    msgs::Twist command;
    LyapunovLaw law = LyapunovLaw::kGlobal;
    bool reversing = false;
    PolarError error;
  };

  // Throws std::invalid_argument on non-positive gains or limits, or a negative eps_rho.
  explicit LyapunovController(const LyapunovOptions& options = {});

  const LyapunovOptions& options() const { return options_; }
  // A non-finite pose or goal gives a zero command and leaves the latches unchanged.
  Output compute(const geometry::Pose2D& pose, const geometry::Pose2D& goal);
  void reset();

 private:
  LyapunovLaw select_law(const PolarError& error);
  bool select_reversing(double alpha_rad);
  msgs::Twist global_law(const PolarError& error, bool reversing) const;
  msgs::Twist local_law(const PolarError& error) const;
  msgs::Twist clamp(const msgs::Twist& command) const;

  LyapunovOptions options_;
  LyapunovLaw law_ = LyapunovLaw::kGlobal;
  std::optional<bool> reversing_;
};

}  // namespace mobot::control
