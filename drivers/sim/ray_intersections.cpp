#include "drivers/sim/ray_intersections.h"

#include <cmath>
#include <limits>

#include "core/numeric/constants.h"

namespace mobot::sim {
namespace {

// The nearer root of a t^2 + b t + c = 0 when both are ahead of the origin, else nullopt (a
// miss, or an origin inside where c <= 0).
std::optional<double> entry_root(double a, double b, double c) {
  if (a <= 0.0 || c <= 0.0) return std::nullopt;
  const double discriminant = b * b - 4.0 * a * c;
  if (discriminant < 0.0) return std::nullopt;
  const double t = (-b - std::sqrt(discriminant)) / (2.0 * a);
  if (t <= 0.0) return std::nullopt;
  return t;
}

// The ray's entry into [min, max] along one axis, narrowing [t_enter, t_exit]; false on a miss.
bool clip_slab(double origin, double direction, double min, double max, double& t_enter,
               double& t_exit, bool& entered_here) {
  entered_here = false;
  if (direction == 0.0) return origin >= min && origin <= max;
  const double t_a = (min - origin) / direction;
  const double t_b = (max - origin) / direction;
  const double t_near = std::fmin(t_a, t_b);
  if (t_near > t_enter) {
    t_enter = t_near;
    entered_here = true;
  }
  t_exit = std::fmin(t_exit, std::fmax(t_a, t_b));
  return t_enter <= t_exit;
}

}  // namespace

std::optional<SurfaceHit> intersect_sphere(const Vec3& origin, const Vec3& direction,
                                           const Vec3& centre, double radius_m) {
  const Vec3 offset = origin - centre;
  const auto t = entry_root(dot(direction, direction), 2.0 * dot(direction, offset),
                            dot(offset, offset) - radius_m * radius_m);
  if (!t) return std::nullopt;
  return SurfaceHit{*t, (1.0 / radius_m) * (offset + *t * direction)};
}

std::optional<SurfaceHit> intersect_upright_cylinder(const Vec3& origin, const Vec3& direction,
                                                     double axis_x_m, double axis_y_m,
                                                     double radius_m, double min_z_m,
                                                     double max_z_m) {
  const double offset_x = origin.x - axis_x_m;
  const double offset_y = origin.y - axis_y_m;
  const double radius_sq = radius_m * radius_m;
  const bool inside_column = offset_x * offset_x + offset_y * offset_y <= radius_sq;
  if (inside_column && origin.z >= min_z_m && origin.z <= max_z_m) return std::nullopt;

  if (const auto t = entry_root(direction.x * direction.x + direction.y * direction.y,
                                2.0 * (direction.x * offset_x + direction.y * offset_y),
                                offset_x * offset_x + offset_y * offset_y - radius_sq)) {
    const double z = origin.z + *t * direction.z;
    if (z >= min_z_m && z <= max_z_m) {
      return SurfaceHit{*t,
                        {(offset_x + *t * direction.x) / radius_m,
                         (offset_y + *t * direction.y) / radius_m, 0.0}};
    }
  }
  // Not through the side: through a cap, which only the cap facing the origin can be.
  if (direction.z == 0.0) return std::nullopt;
  const bool from_above = origin.z > max_z_m;
  if (!from_above && origin.z >= min_z_m) return std::nullopt;
  const double cap_z = from_above ? max_z_m : min_z_m;
  const double t = (cap_z - origin.z) / direction.z;
  if (t <= 0.0) return std::nullopt;
  const double x = offset_x + t * direction.x;
  const double y = offset_y + t * direction.y;
  if (x * x + y * y > radius_sq) return std::nullopt;
  return SurfaceHit{t, {0.0, 0.0, from_above ? 1.0 : -1.0}};
}

std::optional<SurfaceHit> intersect_box(const Vec3& origin, const Vec3& direction,
                                        const Box3D& box) {
  double t_enter = -kInfinity;
  double t_exit = kInfinity;
  bool entered_x = false;
  bool entered_y = false;
  bool entered_z = false;
  if (!clip_slab(origin.x, direction.x, box.min_x_m, box.max_x_m, t_enter, t_exit, entered_x) ||
      !clip_slab(origin.y, direction.y, box.min_y_m, box.max_y_m, t_enter, t_exit, entered_y) ||
      !clip_slab(origin.z, direction.z, box.min_z_m, box.max_z_m, t_enter, t_exit, entered_z)) {
    return std::nullopt;
  }
  if (t_enter <= 0.0) return std::nullopt;
  // The last slab to be entered is the face the ray comes through; it faces against the ray.
  Vec3 normal;
  if (entered_z) {
    normal.z = direction.z > 0.0 ? -1.0 : 1.0;
  } else if (entered_y) {
    normal.y = direction.y > 0.0 ? -1.0 : 1.0;
  } else {
    normal.x = direction.x > 0.0 ? -1.0 : 1.0;
  }
  return SurfaceHit{t_enter, normal};
}

}  // namespace mobot::sim
