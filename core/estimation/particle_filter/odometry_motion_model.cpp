#include "core/estimation/particle_filter/odometry_motion_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace mobot::estimation {
namespace {

bool valid_alpha(double alpha) { return alpha >= 0.0 && std::isfinite(alpha); }

// The rotation's distance from pure forward or pure backward travel.
double rotation_noise_rad(double rotation_rad) {
  const double a = std::abs(geometry::wrap_angle(rotation_rad));
  return std::min(a, std::numbers::pi - a);
}

double gaussian(std::mt19937_64& rng, double sigma) {
  if (!(sigma > 0.0)) return 0.0;
  return std::normal_distribution<double>(0.0, sigma)(rng);
}

}  // namespace

OdometryMotionModel::OdometryMotionModel(const OdometryMotionModelOptions& options)
    : options_(options) {
  if (!valid_alpha(options.alpha1) || !valid_alpha(options.alpha2) ||
      !valid_alpha(options.alpha3) || !valid_alpha(options.alpha4) ||
      !valid_alpha(options.min_translation_for_bearing_m)) {
    throw std::invalid_argument("odometry motion model: alphas must be finite and >= 0");
  }
}

OdometryStep OdometryMotionModel::step(const geometry::Pose2D& odom_before,
                                       const geometry::Pose2D& odom_after) const {
  const double dx = odom_after.x - odom_before.x;
  const double dy = odom_after.y - odom_before.y;
  OdometryStep step;
  step.trans_m = std::hypot(dx, dy);
  step.rot1_rad = step.trans_m < options_.min_translation_for_bearing_m
                      ? 0.0
                      : geometry::wrap_angle(std::atan2(dy, dx) - odom_before.theta);
  step.rot2_rad = geometry::wrap_angle(geometry::wrap_angle(odom_after.theta - odom_before.theta) -
                                       step.rot1_rad);
  const double rot1_noise = rotation_noise_rad(step.rot1_rad);
  const double rot2_noise = rotation_noise_rad(step.rot2_rad);
  const double trans2 = step.trans_m * step.trans_m;
  step.rot1_sigma_rad =
      std::sqrt(options_.alpha1 * rot1_noise * rot1_noise + options_.alpha2 * trans2);
  step.trans_sigma_m =
      std::sqrt(options_.alpha3 * trans2 +
                options_.alpha4 * (rot1_noise * rot1_noise + rot2_noise * rot2_noise));
  step.rot2_sigma_rad =
      std::sqrt(options_.alpha1 * rot2_noise * rot2_noise + options_.alpha2 * trans2);
  return step;
}

geometry::Pose2D OdometryMotionModel::sample(const OdometryStep& step, const geometry::Pose2D& pose,
                                             std::mt19937_64& rng) const {
  const double rot1 = step.rot1_rad - gaussian(rng, step.rot1_sigma_rad);
  const double trans = step.trans_m - gaussian(rng, step.trans_sigma_m);
  const double rot2 = step.rot2_rad - gaussian(rng, step.rot2_sigma_rad);
  return {pose.x + trans * std::cos(pose.theta + rot1),
          pose.y + trans * std::sin(pose.theta + rot1),
          geometry::wrap_angle(pose.theta + rot1 + rot2)};
}

}  // namespace mobot::estimation
