#pragma once

#include <optional>

namespace mobot::vision {

// A viewing direction from the omnidirectional camera's single viewpoint, in the base frame:
// azimuth CCW from the robot's heading, elevation up from the horizontal.
struct OmniDirection {
  double azimuth_rad = 0.0;
  double elevation_rad = 0.0;
};

struct OmniPixel {
  double u = 0.0;  // column, left to right
  double v = 0.0;  // row, top to bottom
};

// The camera looking up into a hyperbolic mirror (R1's omni camera), as the unified central
// catadioptric model (Geyer and Daniilidis; Mei and Rives) describes it: a direction on the unit
// sphere s = (cos e cos a, cos e sin a, -sin e) projects to s_xy / (s_z + xi), scaled by the focal
// length. A hyperbolic mirror has 0 < xi < 1. The radius from the image centre is then
//   r(e) = f cos(e) / (xi - sin(e)),
// growing with elevation: the floor near the robot is near the centre, the horizon at r = f / xi,
// and what is above it further out. The image is flipped as the driver delivers it, so it reads
// like a view from above with the robot's heading up: azimuth a lies at (cx - r sin a, cy - r cos a).
struct OmniCameraModel {
  int width_px = 480;
  int height_px = 480;
  double centre_u_px = 240.0;
  double centre_v_px = 240.0;
  double focal_px = 114.0;
  double xi = 0.8;
  // The ring of the image the mirror fills: below the lower bound the camera sees itself, above the
  // upper one the mirror's rim.
  double min_elevation_rad = -1.0471975511965976;  // -60 deg
  double max_elevation_rad = 0.3490658503988659;   // +20 deg

  double radius_px(double elevation_rad) const;
  // The elevation seen at this radius; the inverse of radius_px.
  double elevation_rad(double radius_px) const;
  // nullopt for a direction outside the mirror's ring.
  std::optional<OmniPixel> project(const OmniDirection& direction) const;
  // nullopt for a pixel outside the mirror's ring.
  std::optional<OmniDirection> direction(const OmniPixel& pixel) const;
};

}  // namespace mobot::vision
