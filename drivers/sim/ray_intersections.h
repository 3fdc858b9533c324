#pragma once

#include <optional>

#include "drivers/sim/world.h"

namespace mobot::sim {

struct Vec3 {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
};

inline Vec3 operator+(const Vec3& a, const Vec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(double s, const Vec3& a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// Where a ray origin + t * direction first enters a solid, t in units of `direction` (which need
// not be unit length, so a camera can pass its un-normalised pixel ray), and the outward unit
// normal there. A ray starting inside the solid does not see it: a camera inside an object would
// otherwise see nothing else.
struct SurfaceHit {
  double t = 0.0;
  Vec3 normal;
};

std::optional<SurfaceHit> intersect_sphere(const Vec3& origin, const Vec3& direction,
                                           const Vec3& centre, double radius_m);

// A cylinder standing upright from min_z_m to max_z_m, with both end caps.
std::optional<SurfaceHit> intersect_upright_cylinder(const Vec3& origin, const Vec3& direction,
                                                     double axis_x_m, double axis_y_m,
                                                     double radius_m, double min_z_m,
                                                     double max_z_m);

std::optional<SurfaceHit> intersect_box(const Vec3& origin, const Vec3& direction,
                                        const Box3D& box);

}  // namespace mobot::sim
