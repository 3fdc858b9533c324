#pragma once

#include <cstdint>
#include <numbers>
#include <optional>
#include <vector>

#include "drivers/sim/camera_scene.h"
#include "drivers/sim/ray_intersections.h"

namespace mobot::sim {

// A colour in grey levels (0..255, may exceed 255 before clamping), in OpenCV's channel order.
struct Bgr {
  float b = 0.0f;
  float g = 0.0f;
  float r = 0.0f;
};

// A solid of the scene prepared for one frame: its shape, an axis-aligned box around it (for the
// renderers to find the pixels it may cover) and how it looks.
struct SceneSolid {
  enum class Shape : std::uint8_t { kSphere, kCylinder, kBox };
  Shape shape = Shape::kBox;
  Box3D bounds;  // the box itself for kBox
  Vec3 centre;   // a sphere's centre; a cylinder's axis (x, y)
  double radius_m = 0.0;
  Bgr color;
  // A lit object (E2's landmark is a lamp) keeps its colour at any distance and from any side.
  bool lit = false;
};

// What one eye point sees along any ray into the scene: the background (floor, walls, ceiling or
// sky) and the solids drawn over it. Walls come from one horizontal ray cast per azimuth bin,
// cast the first time a pixel looks that way and reused by every pixel that looks the same way
// (a column of a level camera, a spoke of the omni image). Objects are intersected exactly.
class SceneShader {
 public:
  struct Sample {
    Bgr color;
    double t = 0.0;  // ray parameter of the surface, +infinity for the sky
  };

  // azimuth_step_rad: the width of a wall bin; a fraction of a pixel keeps wall edges sharp.
  SceneShader(const CameraScene& scene, const Vec3& eye, double azimuth_step_rad);

  // Along eye + t * direction (direction need not be unit length; t is in its units).
  Sample background(const Vec3& direction);

  const std::vector<SceneSolid>& solids() const { return solids_; }
  std::optional<SurfaceHit> intersect(const SceneSolid& solid, const Vec3& direction) const;
  Bgr shade(const SceneSolid& solid, const SurfaceHit& hit, const Vec3& direction) const;

  const Vec3& eye() const { return eye_; }

 private:
  // The wall seen at one azimuth bin's centre.
  struct WallSample {
    float distance_m = 0.0f;  // horizontal; +infinity: no wall within range
    float along_m = 0.0f;     // position of the hit along the wall, for its texture
    bool faces_x = false;     // a face of constant grid x (its normal lies along the grid's x axis)
    bool cast = false;
  };

  const WallSample& wall_at(double azimuth_rad) {
    auto bin = static_cast<std::size_t>((azimuth_rad + std::numbers::pi) * bins_per_rad_);
    if (bin >= walls_.size()) bin = walls_.size() - 1;
    WallSample& wall = walls_[bin];
    if (!wall.cast) cast_wall(bin, wall);
    return wall;
  }
  void cast_wall(std::size_t bin, WallSample& wall) const;
  void add_solids(const CameraScene& scene);

  Bgr wall_color(const WallSample& wall, double z_m, double distance_m) const;
  Bgr floor_color(double x_m, double y_m, double distance_m) const;
  Bgr ceiling_color(double distance_m) const;

  const CameraScene& scene_;
  Vec3 eye_;
  double bins_per_rad_ = 0.0;
  std::vector<WallSample> walls_;
  std::vector<SceneSolid> solids_;
};

}  // namespace mobot::sim
