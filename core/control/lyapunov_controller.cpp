#include "core/control/lyapunov_controller.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/numeric/finite.h"

namespace mobot::control {
namespace {

using geometry::wrap_angle;

double sinc(double x) {
  // sin(x)/x -> 1 at 0; the series keeps full precision where the quotient would not.
  return std::abs(x) < 1e-4 ? 1.0 - x * x / 6.0 : std::sin(x) / x;
}

}  // namespace

double min_eps_rho(double max_rho_error_m, double max_speed_error_mps, double k_v) {
  return max_rho_error_m + max_speed_error_mps / k_v;
}

double PolarError::lateral_m() const { return std::abs(rho_m * std::sin(phi_rad)); }

PolarError polar_error(const geometry::Pose2D& pose, const geometry::Pose2D& goal) {
  const double dx = goal.x - pose.x;
  const double dy = goal.y - pose.y;
  const double bearing = std::atan2(dy, dx);
  return {std::hypot(dx, dy), wrap_angle(bearing - pose.theta), wrap_angle(bearing - goal.theta),
          wrap_angle(pose.theta - goal.theta)};
}

LyapunovController::LyapunovController(const LyapunovOptions& options) : options_(options) {
  const LyapunovGains& g = options.gains;
  if (!finite_positive(g.k_v) || !finite_positive(g.k_alpha) || !finite_positive(g.k_theta) ||
      !finite_positive(g.h) || !finite_positive(options.max_linear_mps) ||
      !finite_positive(options.max_angular_radps)) {
    throw std::invalid_argument("Lyapunov gains and limits must be positive and finite");
  }
  if (!std::isfinite(options.eps_rho_m) || options.eps_rho_m < 0.0 ||
      !(options.local_exit_factor >= 1.0) || std::isnan(options.local_entry_max_lateral_m) ||
      !(options.reverse_hysteresis_rad >= 0.0)) {
    throw std::invalid_argument("Lyapunov switching options out of range");
  }
}

void LyapunovController::reset() {
  law_ = LyapunovLaw::kGlobal;
  reversing_.reset();
}

LyapunovLaw LyapunovController::select_law(const PolarError& error) {
  if (!options_.two_law) return LyapunovLaw::kGlobal;
  const double lateral = error.lateral_m();
  if (law_ == LyapunovLaw::kGlobal) {
    if (error.rho_m < options_.eps_rho_m && lateral < options_.local_entry_max_lateral_m) {
      law_ = LyapunovLaw::kLocal;
    }
  } else if (error.rho_m > options_.local_exit_factor * options_.eps_rho_m ||
             lateral > options_.local_exit_factor * options_.local_entry_max_lateral_m) {
    law_ = LyapunovLaw::kGlobal;
  }
  return law_;
}

bool LyapunovController::select_reversing(double alpha_rad) {
  if (!options_.allow_reverse) return false;
  const double behind = std::abs(alpha_rad) - std::numbers::pi / 2.0;
  if (!reversing_) {
    reversing_ = behind > 0.0;
  } else if (!*reversing_ && behind > options_.reverse_hysteresis_rad) {
    reversing_ = true;
  } else if (*reversing_ && behind < -options_.reverse_hysteresis_rad) {
    reversing_ = false;
  }
  return *reversing_;
}

msgs::Twist LyapunovController::global_law(const PolarError& error, bool reversing) const {
  const LyapunovGains& g = options_.gains;
  // Reversing: the same law in the frame of the robot's rear, whose heading is theta + pi.
  const double alpha = reversing ? wrap_angle(error.alpha_rad - std::numbers::pi) : error.alpha_rad;
  const double phi = reversing ? wrap_angle(error.phi_rad - std::numbers::pi) : error.phi_rad;
  const double v = g.k_v * error.rho_m * std::cos(alpha);
  const double w = g.k_alpha * alpha + g.k_v * sinc(alpha) * std::cos(alpha) * (alpha + g.h * phi);
  if (reversing) return {-v, w};
  // Forward only: a goal behind makes cos(alpha) < 0; turn on the spot instead of backing up.
  return {options_.allow_reverse ? v : std::max(v, 0.0), w};
}

msgs::Twist LyapunovController::local_law(const PolarError& error) const {
  const LyapunovGains& g = options_.gains;
  // cos(alpha) carries the sign: a goal slightly behind is reached by backing up.
  const double v = g.k_v * error.rho_m * std::cos(error.alpha_rad);
  return {options_.allow_reverse ? v : std::max(v, 0.0), -g.k_theta * error.heading_error_rad};
}

msgs::Twist LyapunovController::clamp(const msgs::Twist& command) const {
  return {
      std::clamp(command.linear_mps, -options_.max_linear_mps, options_.max_linear_mps),
      std::clamp(command.angular_radps, -options_.max_angular_radps, options_.max_angular_radps)};
}

LyapunovController::Output LyapunovController::compute(const geometry::Pose2D& pose,
                                                       const geometry::Pose2D& goal) {
  Output out;
  if (!geometry::is_finite(pose) || !geometry::is_finite(goal)) return out;
  out.error = polar_error(pose, goal);
  out.law = select_law(out.error);
  if (out.law == LyapunovLaw::kLocal) {
    out.command = clamp(local_law(out.error));
    out.reversing = out.command.linear_mps < 0.0;
  } else {
    out.reversing = select_reversing(out.error.alpha_rad);
    out.command = clamp(global_law(out.error, out.reversing));
  }
  return out;
}

}  // namespace mobot::control
