#include "core/vision/omni_camera_model.h"

#include <cmath>

namespace mobot::vision {

double OmniCameraModel::radius_px(double elevation_rad) const {
  return focal_px * std::cos(elevation_rad) / (xi - std::sin(elevation_rad));
}

double OmniCameraModel::elevation_rad(double radius) const {
  // r (xi - sin e) = f cos e  <=>  r xi = R sin(e + delta), R = hypot(r, f), delta = atan2(f, r).
  const double hyp = std::hypot(radius, focal_px);
  return std::asin(radius * xi / hyp) - std::atan2(focal_px, radius);
}

std::optional<OmniPixel> OmniCameraModel::project(const OmniDirection& direction) const {
  if (!(direction.elevation_rad >= min_elevation_rad &&
        direction.elevation_rad <= max_elevation_rad)) {
    return std::nullopt;
  }
  const double r = radius_px(direction.elevation_rad);
  return OmniPixel{centre_u_px - r * std::sin(direction.azimuth_rad),
                   centre_v_px - r * std::cos(direction.azimuth_rad)};
}

std::optional<OmniDirection> OmniCameraModel::direction(const OmniPixel& pixel) const {
  const double du = pixel.u - centre_u_px;
  const double dv = pixel.v - centre_v_px;
  const double r = std::hypot(du, dv);
  if (r < radius_px(min_elevation_rad) || r > radius_px(max_elevation_rad)) return std::nullopt;
  return OmniDirection{std::atan2(-du, -dv), elevation_rad(r)};
}

}  // namespace mobot::vision
