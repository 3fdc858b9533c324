#include "drivers/sim/scene_shader.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/numeric/constants.h"

namespace mobot::sim {
namespace {

constexpr double kHalfPi = 1.57079632679489661923;
constexpr double kPi = 3.14159265358979323846;

// Surfaces darken with distance as a room's lamps fall off; lit objects do not.
constexpr double kFalloff_m = 20.0;
// The light comes from above, a little from one side, so that a sphere looks round and the walls
// of a box differ.
constexpr Vec3 kLight{0.33, 0.24, 0.91};

constexpr Bgr kWall{196.0f, 212.0f, 222.0f};  // off-white, barely saturated: no hue to track
constexpr Bgr kSkirting{86.0f, 92.0f, 98.0f};
constexpr double kSkirting_m = 0.10;
constexpr double kPanel_m = 1.2;  // seams between wall panels
constexpr double kSeam_m = 0.03;
constexpr double kStripe_m = 0.15;  // wallpaper stripes: texture for optical flow and scale
// A face of constant grid x is lit less than one of constant grid y, so corners read as corners.
constexpr double kFacesXShade = 0.80;
constexpr Bgr kFloorLight{160.0f, 166.0f, 170.0f};
constexpr Bgr kFloorDark{112.0f, 118.0f, 124.0f};
// Beyond this the tiles are smaller than a pixel: fade the checker out instead of aliasing it.
constexpr double kTileFade_m = 12.0;
constexpr Bgr kCeiling{226.0f, 228.0f, 228.0f};
constexpr Bgr kSky{235.0f, 206.0f, 150.0f};
constexpr Bgr kLandmark{30.0f, 28.0f, 225.0f};  // E2's red lamp
constexpr Bgr kObstacle{128.0f, 128.0f, 128.0f};
constexpr Bgr kBox{150.0f, 132.0f, 118.0f};  // blue-grey furniture: not red, not skin

// atan2 to about 1e-5 rad (Abramowitz and Stegun 4.4.47 on [0, 1], then the octant): std::atan2
// per pixel would cost a third of the frame, and a bin is 100 times wider than the error.
double fast_atan2(double y, double x) {
  const double ax = std::fabs(x);
  const double ay = std::fabs(y);
  const double big = std::max(ax, ay);
  if (big == 0.0) return 0.0;
  const double a = std::min(ax, ay) / big;
  const double s = a * a;
  double angle =
      a *
      (0.99997726 + s * (-0.33262347 +
                         s * (0.19354346 + s * (-0.11643287 + s * (0.05265332 - s * 0.01172120)))));
  if (ay > ax) angle = kHalfPi - angle;
  if (x < 0.0) angle = kPi - angle;
  return y < 0.0 ? -angle : angle;
}

// std::floor is a library call without SSE4.1, and the textures call it per pixel.
long floor_to_long(double value) {
  const auto truncated = static_cast<long>(value);
  return truncated - (value < static_cast<double>(truncated) ? 1 : 0);
}

Bgr scaled(const Bgr& color, double factor) {
  const auto f = static_cast<float>(factor);
  return {color.b * f, color.g * f, color.r * f};
}

Bgr mixed(const Bgr& a, const Bgr& b, double weight_b) {
  const auto w = static_cast<float>(weight_b);
  return {a.b + w * (b.b - a.b), a.g + w * (b.g - a.g), a.r + w * (b.r - a.r)};
}

double falloff(double distance_m) { return kFalloff_m / (kFalloff_m + distance_m); }

Vec3 unit(const Vec3& v) { return (1.0 / std::sqrt(dot(v, v))) * v; }

Bgr to_bgr(const RgbColor& color) {
  return {static_cast<float>(color.b), static_cast<float>(color.g), static_cast<float>(color.r)};
}

}  // namespace

SceneShader::SceneShader(const CameraScene& scene, const Vec3& eye, double azimuth_step_rad)
    : scene_(scene), eye_(eye) {
  const auto bins = static_cast<std::size_t>(std::ceil(2.0 * kPi / azimuth_step_rad));
  walls_.resize(std::max<std::size_t>(bins, 1));
  bins_per_rad_ = static_cast<double>(walls_.size()) / (2.0 * kPi);
  add_solids(scene);
}

void SceneShader::add_solids(const CameraScene& scene) {
  const CameraSceneOptions& options = scene.options;
  const auto cylinder = [this](double x_m, double y_m, double radius_m, double height_m,
                               const Bgr& color, bool lit) {
    solids_.push_back({SceneSolid::Shape::kCylinder,
                       Box3D{x_m - radius_m,
                             y_m - radius_m,
                             x_m + radius_m,
                             y_m + radius_m,
                             0.0,
                             height_m,
                             {},
                             false},
                       {x_m, y_m, 0.0},
                       radius_m,
                       color,
                       lit});
  };
  for (const Landmark& landmark : scene.world.landmarks) {
    cylinder(landmark.x_m, landmark.y_m, options.landmark_radius_m, options.landmark_height_m,
             kLandmark, true);
  }
  for (const SceneCylinder& obstacle : scene.obstacles) {
    cylinder(obstacle.x_m, obstacle.y_m, obstacle.radius_m, obstacle.height_m, kObstacle, false);
  }
  for (const Box3D& box : scene.world.boxes) {
    solids_.push_back({SceneSolid::Shape::kBox, box, {}, 0.0, kBox, false});
  }
  for (const SceneSphere& sphere : scene.targets) {
    const double r = sphere.radius_m;
    solids_.push_back({SceneSolid::Shape::kSphere,
                       Box3D{sphere.x_m - r,
                             sphere.y_m - r,
                             sphere.x_m + r,
                             sphere.y_m + r,
                             sphere.z_m - r,
                             sphere.z_m + r,
                             {},
                             false},
                       {sphere.x_m, sphere.y_m, sphere.z_m},
                       r,
                       to_bgr(sphere.color),
                       false});
  }
}

void SceneShader::cast_wall(std::size_t bin, WallSample& wall) const {
  wall.cast = true;
  const double azimuth_rad = -kPi + (static_cast<double>(bin) + 0.5) / bins_per_rad_;
  const auto distance_m =
      scene_.walls.cast({eye_.x, eye_.y}, azimuth_rad, scene_.options.max_range_m);
  if (!distance_m) {
    wall.distance_m = std::numeric_limits<float>::infinity();
    return;
  }
  wall.distance_m = static_cast<float>(*distance_m);
  // The caster stops exactly on a cell boundary: the grid coordinate closer to a whole number
  // tells which face it crossed.
  const mapping::OccupancyGrid& grid = scene_.world.floor;
  const double hit_x = eye_.x + *distance_m * std::cos(azimuth_rad) - grid.origin().x;
  const double hit_y = eye_.y + *distance_m * std::sin(azimuth_rad) - grid.origin().y;
  const double c = std::cos(grid.origin().theta);
  const double s = std::sin(grid.origin().theta);
  const double cell_x = (c * hit_x + s * hit_y) / grid.resolution_m();
  const double cell_y = (-s * hit_x + c * hit_y) / grid.resolution_m();
  wall.faces_x = std::fabs(cell_x - std::round(cell_x)) < std::fabs(cell_y - std::round(cell_y));
  wall.along_m = static_cast<float>((wall.faces_x ? cell_y : cell_x) * grid.resolution_m());
}

SceneShader::Sample SceneShader::background(const Vec3& direction) {
  const double horizontal_sq = direction.x * direction.x + direction.y * direction.y;
  const double length = std::sqrt(horizontal_sq + direction.z * direction.z);
  const double wall_height_m = scene_.options.wall_height_m;
  if (horizontal_sq > 0.0) {
    const WallSample& wall = wall_at(fast_atan2(direction.y, direction.x));
    const double t = wall.distance_m / std::sqrt(horizontal_sq);
    const double z_m = eye_.z + t * direction.z;
    if (z_m >= 0.0 && z_m <= wall_height_m) {
      return {wall_color(wall, z_m, t * length), t};
    }
  }
  if (direction.z < 0.0) {
    const double t = -eye_.z / direction.z;
    return {floor_color(eye_.x + t * direction.x, eye_.y + t * direction.y, t * length), t};
  }
  if (direction.z > 0.0 && scene_.options.ceiling && eye_.z < wall_height_m) {
    const double t = (wall_height_m - eye_.z) / direction.z;
    return {ceiling_color(t * length), t};
  }
  return {kSky, kInfinity};
}

Bgr SceneShader::wall_color(const WallSample& wall, double z_m, double distance_m) const {
  const double shade = (wall.faces_x ? kFacesXShade : 1.0) * falloff(distance_m);
  if (z_m < kSkirting_m) return scaled(kSkirting, shade);
  const double along_m = wall.along_m;
  const double panels = along_m * (1.0 / kPanel_m);
  if (panels - static_cast<double>(floor_to_long(panels)) < kSeam_m / kPanel_m) {
    return scaled(kWall, 0.6 * shade);
  }
  const bool stripe = (floor_to_long(along_m * (1.0 / kStripe_m)) & 1) == 0;
  return scaled(kWall, (stripe ? 0.95 : 1.0) * shade);
}

Bgr SceneShader::floor_color(double x_m, double y_m, double distance_m) const {
  const Bgr average = mixed(kFloorLight, kFloorDark, 0.5);
  if (distance_m >= kTileFade_m) return scaled(average, falloff(distance_m));
  const double tile_m = scene_.options.floor_tile_m;
  const long column = floor_to_long(x_m / tile_m);
  const long row = floor_to_long(y_m / tile_m);
  const Bgr tile = ((column + row) & 1) == 0 ? kFloorLight : kFloorDark;
  return scaled(mixed(tile, average, distance_m / kTileFade_m), falloff(distance_m));
}

Bgr SceneShader::ceiling_color(double distance_m) const {
  return scaled(kCeiling, falloff(distance_m));
}

std::optional<SurfaceHit> SceneShader::intersect(const SceneSolid& solid,
                                                 const Vec3& direction) const {
  switch (solid.shape) {
    case SceneSolid::Shape::kSphere:
      return intersect_sphere(eye_, direction, solid.centre, solid.radius_m);
    case SceneSolid::Shape::kCylinder:
      return intersect_upright_cylinder(eye_, direction, solid.centre.x, solid.centre.y,
                                        solid.radius_m, solid.bounds.min_z_m, solid.bounds.max_z_m);
    case SceneSolid::Shape::kBox:
      return intersect_box(eye_, direction, solid.bounds);
  }
  return std::nullopt;
}

Bgr SceneShader::shade(const SceneSolid& solid, const SurfaceHit& hit,
                       const Vec3& direction) const {
  const double lambert = std::max(0.0, dot(hit.normal, unit(kLight)));
  if (solid.lit) return scaled(solid.color, 0.85 + 0.15 * lambert);
  const Vec3 view = unit(direction);
  // Some light from the camera's side too, so the far side of a ball is not black.
  const double facing = std::max(0.0, -dot(hit.normal, view));
  const double distance_m = hit.t * std::sqrt(dot(direction, direction));
  return scaled(solid.color, (0.50 + 0.30 * lambert + 0.20 * facing) * falloff(distance_m));
}

}  // namespace mobot::sim
