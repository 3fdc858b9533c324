#include "core/vision/pan_tilt_head.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace mobot::vision {
namespace {

using Vec3 = std::array<double, 3>;

void require_head(bool condition, const std::string& message) {
  if (!condition) throw std::invalid_argument("PanTiltHeadOptions: " + message);
}

void require_range(double min_rad, double max_rad, const std::string& name) {
  require_head(std::isfinite(min_rad) && std::isfinite(max_rad) && min_rad <= max_rad,
               name + " limits must be finite with min <= max");
}

double step_axis(double current, double target, double max_step) {
  return current + std::clamp(target - current, -max_step, max_step);
}

// The ray through pixel (u, v) in the base frame's orientation, not normalised. The camera looks
// along the tilt link: forward, its left (pan only turns it) and its up (tilt leans it back).
Vec3 pixel_ray_in_base(PanTilt joints, double u_px, double v_px, const PinholeCamera& camera) {
  const double cp = std::cos(joints.pan_rad);
  const double sp = std::sin(joints.pan_rad);
  const double ct = std::cos(joints.tilt_rad);
  const double st = std::sin(joints.tilt_rad);
  const Vec3 forward{cp * ct, sp * ct, st};
  const Vec3 left{-sp, cp, 0.0};
  const Vec3 up{-cp * st, -sp * st, ct};
  const double f = camera.focal_px();
  const double to_left = -(u_px - 0.5 * camera.width_px);
  const double to_up = -(v_px - 0.5 * camera.height_px);
  Vec3 ray{};
  for (std::size_t i = 0; i < 3; ++i) ray[i] = f * forward[i] + to_left * left[i] + to_up * up[i];
  return ray;
}

}  // namespace

PanTiltHead::PanTiltHead(PanTiltHeadOptions options) : options_(options) {
  for (const double length : {options_.l0_m, options_.l1_m, options_.l2_m}) {
    require_head(std::isfinite(length) && length >= 0.0,
                 "l0_m, l1_m, l2_m must be finite and >= 0");
  }
  require_head(std::isfinite(options_.mount_x_m), "mount_x_m must be finite");
  require_range(options_.min_pan_rad, options_.max_pan_rad, "pan");
  require_range(options_.min_tilt_rad, options_.max_tilt_rad, "tilt");
  require_head(std::isfinite(options_.max_pan_rate_rad_s) && options_.max_pan_rate_rad_s > 0.0 &&
                   std::isfinite(options_.max_tilt_rate_rad_s) &&
                   options_.max_tilt_rate_rad_s > 0.0,
               "max_pan_rate_rad_s and max_tilt_rate_rad_s must be finite and > 0");
}

LensPosition PanTiltHead::lens_in_base(PanTilt joints) const {
  const double reach = options_.l2_m * std::cos(joints.tilt_rad);
  return {options_.mount_x_m + reach * std::cos(joints.pan_rad), reach * std::sin(joints.pan_rad),
          options_.l0_m + options_.l1_m + options_.l2_m * std::sin(joints.tilt_rad)};
}

CameraPose PanTiltHead::camera_pose(const geometry::Pose2D& base_in_map, PanTilt joints) const {
  const LensPosition lens = lens_in_base(joints);
  const geometry::Point2D in_map = geometry::transform_point(base_in_map, {lens.x_m, lens.y_m});
  return {in_map.x, in_map.y, lens.z_m, geometry::wrap_angle(base_in_map.theta + joints.pan_rad),
          joints.tilt_rad};
}

PanTilt PanTiltHead::clamp(PanTilt joints) const {
  const auto finite_or_zero = [](double value) { return std::isfinite(value) ? value : 0.0; };
  return {
      std::clamp(finite_or_zero(joints.pan_rad), options_.min_pan_rad, options_.max_pan_rad),
      std::clamp(finite_or_zero(joints.tilt_rad), options_.min_tilt_rad, options_.max_tilt_rad)};
}

PanTilt PanTiltHead::step_towards(PanTilt current, PanTilt target, double dt_s) const {
  const PanTilt from = clamp(current);
  if (!std::isfinite(dt_s) || dt_s <= 0.0) return from;
  const PanTilt to = clamp(target);
  return {step_axis(from.pan_rad, to.pan_rad, options_.max_pan_rate_rad_s * dt_s),
          step_axis(from.tilt_rad, to.tilt_rad, options_.max_tilt_rate_rad_s * dt_s)};
}

PanTilt PanTiltHead::centring_target(PanTilt current, double u_px, double v_px,
                                     const PinholeCamera& camera) const {
  if (!std::isfinite(u_px) || !std::isfinite(v_px)) return clamp(current);
  const Vec3 ray = pixel_ray_in_base(current, u_px, v_px, camera);
  return clamp({std::atan2(ray[1], ray[0]), std::atan2(ray[2], std::hypot(ray[0], ray[1]))});
}

std::optional<geometry::Point2D> PanTiltHead::target_in_base(PanTilt joints, double u_px,
                                                             double v_px, double range_m,
                                                             const PinholeCamera& camera) const {
  if (!std::isfinite(joints.pan_rad) || !std::isfinite(joints.tilt_rad) || !std::isfinite(u_px) ||
      !std::isfinite(v_px) || !std::isfinite(range_m) || range_m <= 0.0) {
    return std::nullopt;
  }
  const Vec3 ray = pixel_ray_in_base(joints, u_px, v_px, camera);
  const double norm = std::hypot(ray[0], ray[1], ray[2]);
  const LensPosition lens = lens_in_base(joints);
  return geometry::Point2D{lens.x_m + range_m * ray[0] / norm, lens.y_m + range_m * ray[1] / norm};
}

double bearing_from_column_linear_rad(double column_px, const PinholeCamera& camera) {
  return -(column_px - 0.5 * camera.width_px) / camera.width_px * camera.horizontal_fov_rad;
}

double bearing_from_column_rad(double column_px, const PinholeCamera& camera) {
  return std::atan(-(column_px - 0.5 * camera.width_px) / camera.focal_px());
}

double elevation_from_row_rad(double row_px, const PinholeCamera& camera) {
  return std::atan(-(row_px - 0.5 * camera.height_px) / camera.focal_px());
}

}  // namespace mobot::vision
