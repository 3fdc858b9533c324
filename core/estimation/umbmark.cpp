#include "core/estimation/umbmark.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace mobot::estimation {
namespace {

std::optional<UmbmarkRunError> centroid(std::span<const UmbmarkRunError> runs) {
  if (runs.empty()) return std::nullopt;
  UmbmarkRunError sum;
  for (const UmbmarkRunError& run : runs) {
    if (!std::isfinite(run.x_m) || !std::isfinite(run.y_m)) return std::nullopt;
    sum.x_m += run.x_m;
    sum.y_m += run.y_m;
  }
  const double n = static_cast<double>(runs.size());
  return UmbmarkRunError{sum.x_m / n, sum.y_m / n};
}

bool valid_params(const OdometryParams& params) {
  return std::isfinite(params.left_wheel_radius_m) && params.left_wheel_radius_m > 0.0 &&
         std::isfinite(params.right_wheel_radius_m) && params.right_wheel_radius_m > 0.0 &&
         std::isfinite(params.track_m) && params.track_m > 0.0;
}

}  // namespace

std::optional<UmbmarkResult> umbmark_calibrate(const OdometryParams& params, double side_m,
                                               std::span<const UmbmarkRunError> cw_runs,
                                               std::span<const UmbmarkRunError> ccw_runs) {
  if (!std::isfinite(side_m) || !(side_m > 0.0) || !valid_params(params)) return std::nullopt;
  const auto cw = centroid(cw_runs);
  const auto ccw = centroid(ccw_runs);
  if (!cw || !ccw) return std::nullopt;

  UmbmarkResult result;
  result.cw_centroid = *cw;
  result.ccw_centroid = *ccw;
  result.systematic_error_m =
      std::max(std::hypot(cw->x_m, cw->y_m), std::hypot(ccw->x_m, ccw->y_m));
  const double eight_l = 8.0 * side_m;
  result.alpha_rad = -((cw->x_m + ccw->x_m) + (cw->y_m - ccw->y_m)) / eight_l;
  result.beta_rad = -((cw->x_m - ccw->x_m) + (cw->y_m + ccw->y_m)) / eight_l;

  constexpr double kQuarterTurn = std::numbers::pi / 2.0;
  if (!(std::abs(result.alpha_rad) < kQuarterTurn)) return std::nullopt;
  result.wheelbase_factor = kQuarterTurn / (kQuarterTurn - result.alpha_rad);
  const double track_m = params.track_m * result.wheelbase_factor;
  // (R + b/2) / (R - b/2) with R = (L/2) / sin(beta/2), written without dividing by sin(beta/2)
  // so that beta = 0 needs no special case.
  const double half_chord_m = side_m / 2.0;
  const double offset_m = track_m / 2.0 * std::sin(result.beta_rad / 2.0);
  if (!(std::abs(offset_m) < half_chord_m)) return std::nullopt;
  result.diameter_ratio = (half_chord_m + offset_m) / (half_chord_m - offset_m);

  result.left_radius_factor = 2.0 / (result.diameter_ratio + 1.0);
  result.right_radius_factor = 2.0 / (1.0 / result.diameter_ratio + 1.0);
  result.corrected = params;
  result.corrected.left_wheel_radius_m *= result.left_radius_factor;
  result.corrected.right_wheel_radius_m *= result.right_radius_factor;
  result.corrected.track_m = track_m;
  return result;
}

double straight_run_error_percent(const geometry::Point2D& intended_end,
                                  const geometry::Point2D& true_end, double run_length_m) {
  if (!(run_length_m > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return 100.0 * std::hypot(true_end.x - intended_end.x, true_end.y - intended_end.y) /
         run_length_m;
}

}  // namespace mobot::estimation
