#include "drivers/sim/camera_renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "drivers/sim/scene_shader.h"

namespace mobot::sim {
namespace {

// The pixel bounds of what an object can cover, grown point by point.
struct Bounds {
  double min_u = std::numeric_limits<double>::infinity();
  double max_u = -std::numeric_limits<double>::infinity();
  double min_v = std::numeric_limits<double>::infinity();
  double max_v = -std::numeric_limits<double>::infinity();

  void add(const cv::Point2d& point) {
    min_u = std::min(min_u, point.x);
    max_u = std::max(max_u, point.x);
    min_v = std::min(min_v, point.y);
    max_v = std::max(max_v, point.y);
  }
  bool empty() const { return min_u > max_u; }
  // One pixel of margin against the elevation table's rounding.
  cv::Rect rect() const {
    const int u0 = static_cast<int>(std::floor(min_u)) - 1;
    const int v0 = static_cast<int>(std::floor(min_v)) - 1;
    return {u0, v0, static_cast<int>(std::ceil(max_u)) + 2 - u0,
            static_cast<int>(std::ceil(max_v)) + 2 - v0};
  }
};


// The centre disc and the corners of the omni image: the camera's own reflection and the mirror's
// mount, dark but not black.
constexpr Bgr kOutsideMirror{24.0f, 24.0f, 24.0f};
// Wall bins a quarter of a column wide (pinhole) or half a pixel at the rim (omni): walls'
// vertical edges land within a pixel of where an exact cast per pixel would put them.
constexpr double kPinholeBinsPerPixel = 4.0;
constexpr double kOmniBinsPerRimPixel = 2.0;
// Per elevation sample of the mirror, in pixels of radius.
constexpr double kMirrorTableStep_px = 1.0 / 16.0;

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

void check_scene(const CameraScene& scene) {
  const CameraSceneOptions& options = scene.options;
  const auto positive = [](double value) { return std::isfinite(value) && value > 0.0; };
  require(positive(options.wall_height_m), "camera scene: wall_height_m must be finite and > 0");
  require(positive(options.landmark_radius_m),
          "camera scene: landmark_radius_m must be finite and > 0");
  require(positive(options.landmark_height_m),
          "camera scene: landmark_height_m must be finite and > 0");
  require(positive(options.floor_tile_m), "camera scene: floor_tile_m must be finite and > 0");
  require(positive(options.max_range_m), "camera scene: max_range_m must be finite and > 0");
}

inline void put(std::uint8_t* pixel, const Bgr& color) {
  // min/max rather than clamp: they compile to branch-free minss/maxss.
  const auto level = [](float value) {
    return static_cast<std::uint8_t>(std::min(std::max(value + 0.5f, 0.0f), 255.0f));
  };
  pixel[0] = level(color.b);
  pixel[1] = level(color.g);
  pixel[2] = level(color.r);
}

std::array<Vec3, 8> corners(const Box3D& box) {
  std::array<Vec3, 8> out;
  for (int i = 0; i < 8; ++i) {
    out[static_cast<std::size_t>(i)] = {(i & 1) ? box.max_x_m : box.min_x_m,
                                        (i & 2) ? box.max_y_m : box.min_y_m,
                                        (i & 4) ? box.max_z_m : box.min_z_m};
  }
  return out;
}

// The pinhole's rays, and the pixels a box may cover.
class PinholeLens {
 public:
  PinholeLens(const vision::CameraPose& pose, const vision::PinholeCamera& camera)
      : width_(camera.width_px),
        height_(camera.height_px),
        focal_px_(camera.focal_px()),
        centre_u_(0.5 * camera.width_px),
        centre_v_(0.5 * camera.height_px),
        forward_{std::cos(pose.pitch_rad) * std::cos(pose.yaw_rad),
                 std::cos(pose.pitch_rad) * std::sin(pose.yaw_rad), std::sin(pose.pitch_rad)},
        left_{-std::sin(pose.yaw_rad), std::cos(pose.yaw_rad), 0.0},
        up_{-std::sin(pose.pitch_rad) * std::cos(pose.yaw_rad),
            -std::sin(pose.pitch_rad) * std::sin(pose.yaw_rad), std::cos(pose.pitch_rad)} {}

  int width() const { return width_; }
  int height() const { return height_; }
  double focal_px() const { return focal_px_; }

  bool direction(int u, int v, Vec3& out) const {
    out = focal_px_ * forward_ + (centre_u_ - u) * left_ + (centre_v_ - v) * up_;
    return true;
  }

  // The bounding rectangle of the part of the box in front of the camera: its corners there and
  // where its edges cross the near plane (the part behind projects nowhere).
  cv::Rect footprint(const Box3D& box, const Vec3& eye) const {
    std::array<Vec3, 8> offsets = corners(box);
    std::array<double, 8> depths{};
    for (std::size_t i = 0; i < offsets.size(); ++i) {
      offsets[i] = offsets[i] - eye;
      depths[i] = dot(offsets[i], forward_);
    }
    Bounds bounds;
    for (std::size_t i = 0; i < offsets.size(); ++i) {
      if (depths[i] >= kNear_m) bounds.add(project(offsets[i], depths[i]));
      // The edges from corner i along x, y and z (the corner with that bit set).
      for (std::size_t axis_bit = 1; axis_bit < 8; axis_bit <<= 1) {
        const std::size_t j = i | axis_bit;
        if (j == i || (depths[i] >= kNear_m) == (depths[j] >= kNear_m)) continue;
        const double fraction = (kNear_m - depths[i]) / (depths[j] - depths[i]);
        bounds.add(project(offsets[i] + fraction * (offsets[j] - offsets[i]), kNear_m));
      }
    }
    if (bounds.empty()) return {};
    return clipped(bounds);
  }

 private:
  static constexpr double kNear_m = 1e-3;

  cv::Point2d project(const Vec3& offset, double depth) const {
    return {centre_u_ - focal_px_ * dot(offset, left_) / depth,
            centre_v_ - focal_px_ * dot(offset, up_) / depth};
  }

  cv::Rect clipped(const Bounds& bounds) const {
    // Pixel centres are at integers: a pixel whose centre lies within the bounds may be covered.
    const auto low = [](double value, int size) {
      return static_cast<int>(std::clamp(std::floor(value), 0.0, 1.0 * size));
    };
    const auto high = [](double value, int size) {
      return static_cast<int>(std::clamp(std::ceil(value) + 1.0, 0.0, 1.0 * size));
    };
    const int u0 = low(bounds.min_u, width_);
    const int v0 = low(bounds.min_v, height_);
    return {u0, v0, high(bounds.max_u, width_) - u0, high(bounds.max_v, height_) - v0};
  }

  int width_;
  int height_;
  double focal_px_;
  double centre_u_;
  double centre_v_;
  Vec3 forward_;
  Vec3 left_;
  Vec3 up_;
};

// The omni camera's rays: per pixel the model's azimuth (from the pixel's position around the
// centre, no trigonometry) and elevation (from a table over the radius), turned into the map
// frame by the heading.
class MirrorLens {
 public:
  MirrorLens(const vision::OmniCameraModel& model, double heading_rad)
      : model_(model),
        min_radius_px_(model.radius_px(model.min_elevation_rad)),
        max_radius_px_(model.radius_px(model.max_elevation_rad)),
        heading_rad_(heading_rad),
        heading_cos_(std::cos(heading_rad)),
        heading_sin_(std::sin(heading_rad)) {
    // Sample i covers radii [i, i + 1) steps from the inner edge and holds its middle's elevation.
    const auto samples =
        static_cast<std::size_t>((max_radius_px_ - min_radius_px_) / kMirrorTableStep_px) + 1;
    elevation_cos_.resize(samples);
    elevation_sin_.resize(samples);
    for (std::size_t i = 0; i < samples; ++i) {
      const double elevation_rad = model.elevation_rad(std::min(
          min_radius_px_ + (static_cast<double>(i) + 0.5) * kMirrorTableStep_px, max_radius_px_));
      elevation_cos_[i] = std::cos(elevation_rad);
      elevation_sin_[i] = std::sin(elevation_rad);
    }
  }

  int width() const { return model_.width_px; }
  int height() const { return model_.height_px; }
  double max_radius_px() const { return max_radius_px_; }

  bool direction(int u, int v, Vec3& out) const {
    const double du = u - model_.centre_u_px;
    const double dv = v - model_.centre_v_px;
    const double radius_sq = du * du + dv * dv;
    // The same ring as OmniCameraModel::direction.
    if (radius_sq < min_radius_px_ * min_radius_px_ ||
        radius_sq > max_radius_px_ * max_radius_px_) {
      return false;
    }
    const double radius_px = std::sqrt(radius_sq);
    // Azimuth a sits at (cx - r sin a, cy - r cos a).
    const double azimuth_cos = -dv / radius_px;
    const double azimuth_sin = -du / radius_px;
    // min(): the rim's radius may round up by an ulp.
    const auto sample =
        std::min(static_cast<std::size_t>((radius_px - min_radius_px_) / kMirrorTableStep_px),
                 elevation_cos_.size() - 1);
    const double horizontal = elevation_cos_[sample];
    out = {horizontal * (heading_cos_ * azimuth_cos - heading_sin_ * azimuth_sin),
           horizontal * (heading_sin_ * azimuth_cos + heading_cos_ * azimuth_sin),
           elevation_sin_[sample]};
    return true;
  }

  // The bounding rectangle of the ring sector that holds every direction towards the box's
  // bounding sphere.
  cv::Rect footprint(const Box3D& box, const Vec3& eye) const {
    const cv::Rect whole{0, 0, width(), height()};
    const Vec3 centre{0.5 * (box.min_x_m + box.max_x_m), 0.5 * (box.min_y_m + box.max_y_m),
                      0.5 * (box.min_z_m + box.max_z_m)};
    const Vec3 half{box.max_x_m - centre.x, box.max_y_m - centre.y, box.max_z_m - centre.z};
    const double radius_m = std::sqrt(dot(half, half));
    const Vec3 offset = centre - eye;
    const double distance_m = std::sqrt(dot(offset, offset));
    if (distance_m <= radius_m) return whole;
    const double horizontal_m = std::hypot(offset.x, offset.y);
    const double spread_rad = std::asin(radius_m / distance_m);
    const double elevation_rad = std::atan2(offset.z, horizontal_m);
    const double low_rad = std::max(elevation_rad - spread_rad, model_.min_elevation_rad);
    const double high_rad = std::min(elevation_rad + spread_rad, model_.max_elevation_rad);
    if (low_rad > high_rad) return {};
    const double inner_px = model_.radius_px(low_rad);
    const double outer_px = model_.radius_px(high_rad);
    if (horizontal_m <= radius_m) return around_centre(outer_px);

    const double azimuth_rad = std::atan2(offset.y, offset.x) - heading_rad_;
    const double half_width_rad = std::asin(radius_m / horizontal_m);
    Bounds bounds;
    for (const double radius_px : {inner_px, outer_px}) {
      bounds.add(sector_point(azimuth_rad - half_width_rad, radius_px));
      bounds.add(sector_point(azimuth_rad + half_width_rad, radius_px));
      // Where the arc crosses an axis it reaches its extreme in u or v.
      constexpr double kQuarter = std::numbers::pi / 2;
      for (double axis = std::ceil((azimuth_rad - half_width_rad) / kQuarter) * kQuarter;
           axis <= azimuth_rad + half_width_rad; axis += kQuarter) {
        bounds.add(sector_point(axis, radius_px));
      }
    }
    return bounds.rect() & whole;
  }

 private:
  cv::Point2d sector_point(double azimuth_rad, double radius_px) const {
    return {model_.centre_u_px - radius_px * std::sin(azimuth_rad),
            model_.centre_v_px - radius_px * std::cos(azimuth_rad)};
  }

  cv::Rect around_centre(double radius_px) const {
    Bounds bounds;
    bounds.add({model_.centre_u_px - radius_px, model_.centre_v_px - radius_px});
    bounds.add({model_.centre_u_px + radius_px, model_.centre_v_px + radius_px});
    return bounds.rect() & cv::Rect{0, 0, width(), height()};
  }

  const vision::OmniCameraModel& model_;
  double min_radius_px_;
  double max_radius_px_;
  double heading_rad_;
  double heading_cos_;
  double heading_sin_;
  std::vector<double> elevation_cos_;
  std::vector<double> elevation_sin_;
};

// Background first, then every solid over the pixels it may cover, kept where it is nearer than
// what is there: a per-pixel depth test in units of the pixel's (un-normalised) ray.
template <typename Lens>
cv::Mat render(const CameraScene& scene, const Vec3& eye, const Lens& lens,
               double azimuth_step_rad) {
  SceneShader shader(scene, eye, azimuth_step_rad);
  cv::Mat image(lens.height(), lens.width(), CV_8UC3);
  std::vector<float> depth(static_cast<std::size_t>(lens.width()) *
                           static_cast<std::size_t>(lens.height()));
  for (int v = 0; v < lens.height(); ++v) {
    auto* pixel = image.ptr<std::uint8_t>(v);
    float* nearest = depth.data() + static_cast<std::ptrdiff_t>(v) * lens.width();
    for (int u = 0; u < lens.width(); ++u, pixel += 3, ++nearest) {
      Vec3 direction;
      if (!lens.direction(u, v, direction)) {
        put(pixel, kOutsideMirror);
        *nearest = 0.0f;
        continue;
      }
      const SceneShader::Sample sample = shader.background(direction);
      put(pixel, sample.color);
      *nearest = static_cast<float>(sample.t);
    }
  }
  for (const SceneSolid& solid : shader.solids()) {
    const cv::Rect area = lens.footprint(solid.bounds, eye);
    for (int v = area.y; v < area.y + area.height; ++v) {
      for (int u = area.x; u < area.x + area.width; ++u) {
        Vec3 direction;
        if (!lens.direction(u, v, direction)) continue;
        const auto hit = shader.intersect(solid, direction);
        float& nearest =
            depth[static_cast<std::size_t>(v) * static_cast<std::size_t>(lens.width()) +
                  static_cast<std::size_t>(u)];
        if (!hit || !(hit->t < nearest)) continue;
        nearest = static_cast<float>(hit->t);
        put(image.ptr<std::uint8_t>(v) + std::ptrdiff_t{3} * u,
            shader.shade(solid, *hit, direction));
      }
    }
  }
  return image;
}

}  // namespace

cv::Mat render_perspective(const CameraScene& scene, const vision::CameraPose& pose,
                           const vision::PinholeCamera& camera, const CameraNoise& noise,
                           std::mt19937_64& rng) {
  require(std::isfinite(pose.x_m) && std::isfinite(pose.y_m) && std::isfinite(pose.z_m) &&
              std::isfinite(pose.yaw_rad) && std::isfinite(pose.pitch_rad),
          "perspective camera: the pose must be finite");
  require(camera.width_px > 0 && camera.height_px > 0,
          "perspective camera: width_px and height_px must be > 0");
  require(camera.horizontal_fov_rad > 0.0 && camera.horizontal_fov_rad < std::numbers::pi,
          "perspective camera: horizontal_fov_rad must be in (0, pi)");
  check_scene(scene);
  const PinholeLens lens(pose, camera);
  cv::Mat image = render(scene, {pose.x_m, pose.y_m, pose.z_m}, lens,
                         1.0 / (kPinholeBinsPerPixel * lens.focal_px()));
  noise.apply(image, rng);
  return image;
}

cv::Mat render_omni(const CameraScene& scene, const geometry::Pose2D& base_pose,
                    double camera_height_m, const vision::OmniCameraModel& model,
                    const CameraNoise& noise, std::mt19937_64& rng) {
  require(geometry::is_finite(base_pose) && std::isfinite(camera_height_m),
          "omni camera: the base pose and camera_height_m must be finite");
  require(model.width_px > 0 && model.height_px > 0,
          "omni camera: width_px and height_px must be > 0");
  require(std::isfinite(model.focal_px) && model.focal_px > 0.0 && std::isfinite(model.xi) &&
              std::isfinite(model.centre_u_px) && std::isfinite(model.centre_v_px),
          "omni camera: focal_px must be > 0 and the model finite");
  require(model.min_elevation_rad < model.max_elevation_rad &&
              model.min_elevation_rad > -std::numbers::pi / 2 &&
              std::sin(model.max_elevation_rad) < model.xi,
          "omni camera: the mirror's ring needs -pi/2 < min_elevation_rad < max_elevation_rad "
          "and sin(max_elevation_rad) < xi");
  check_scene(scene);
  const MirrorLens lens(model, base_pose.theta);
  cv::Mat image = render(scene, {base_pose.x, base_pose.y, camera_height_m}, lens,
                         1.0 / (kOmniBinsPerRimPixel * lens.max_radius_px()));
  noise.apply(image, rng);
  return image;
}

}  // namespace mobot::sim
