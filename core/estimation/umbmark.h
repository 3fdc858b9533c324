#pragma once

#include <optional>
#include <span>

#include "core/estimation/wheel_odometry.h"
#include "core/geometry/pose2d.h"

namespace mobot::estimation {

// Return-position error of one UMBmark square run (Borenstein & Feng): where the robot really
// stopped minus where its odometry believes it stopped (the start), in the start frame: x along
// the first leg, y to its left. The robot starts each run heading along +x and drives four legs of
// side L; the clockwise run turns right after each leg, the counter-clockwise run turns left.
struct UmbmarkRunError {
  double x_m = 0.0;
  double y_m = 0.0;
};

struct UmbmarkResult {
  // Centres of gravity of the return errors of each direction.
  UmbmarkRunError cw_centroid;
  UmbmarkRunError ccw_centroid;
  // Borenstein's measure of systematic odometry error: max(|c.g. cw|, |c.g. ccw|).
  double systematic_error_m = 0.0;
  // Type A error: how much each nominal 90 deg turn falls short of 90 deg (wheelbase error).
  double alpha_rad = 0.0;
  // Type B error: heading change over one straight leg, positive to the left (unequal wheels).
  double beta_rad = 0.0;
  // E_d = D_R / D_L actual wheel diameter ratio (relative to the radii the runs were driven with).
  double diameter_ratio = 1.0;
  // E_b = b_actual / b_nominal.
  double wheelbase_factor = 1.0;
  // Radius multipliers c_L = 2 / (E_d + 1), c_R = 2 / (1 / E_d + 1): their mean is 1, so the
  // average wheel size (the distance scale, which UMBmark cannot observe) is kept.
  double left_radius_factor = 1.0;
  double right_radius_factor = 1.0;
  // `params` with both radii and the track corrected.
  OdometryParams corrected;
};

// UMBmark calibration (docs/algorithms.md E1): alpha and beta from the return errors of n clockwise
// and n counter-clockwise runs (Borenstein's x-error formulas, averaged with the equivalent y-error
// ones to halve the effect of measurement noise):
//   alpha = -[(x_cw + x_ccw) + (y_cw - y_ccw)] / 8L,  beta = -[(x_cw - x_ccw) + (y_cw + y_ccw)] /
//   8L, E_b = (pi/2) / (pi/2 - alpha),  R = (L/2) / sin(beta/2),  E_d = (R + b/2) / (R - b/2)
// with b the corrected track. `params` are the ones the runs were driven and dead-reckoned with.
// nullopt when an input is not finite, side_m <= 0, a direction has no runs, or the errors are
// too large for the model (|alpha| >= pi/2, or a curvature tighter than half the track).
std::optional<UmbmarkResult> umbmark_calibrate(const OdometryParams& params, double side_m,
                                               std::span<const UmbmarkRunError> cw_runs,
                                               std::span<const UmbmarkRunError> ccw_runs);

// Score of a straight run for before/after reports: distance between where the robot really ended
// and where it was sent, in percent of the run length (E1 quotes 3.86 % -> 0.09 % over 7 m).
// NaN when run_length_m <= 0.
double straight_run_error_percent(const geometry::Point2D& intended_end,
                                  const geometry::Point2D& true_end, double run_length_m);

}  // namespace mobot::estimation
