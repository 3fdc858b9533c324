#include "drivers/sim/ray_caster.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/numeric/constants.h"

namespace mobot::sim {
namespace {

constexpr std::uint8_t kBlocked = 0;
// The ring of cells just beyond the grid: free but allowing no jump, so a ray reaching it walks
// and leaves the grid.
constexpr std::uint8_t kPadding = 1;
constexpr int kMaxJumpCells = 253;
// A jump shorter than this costs more (re-seeding the cell walk) than walking the cells.
constexpr int kMinJumpCells = 2;
// While walking, go back to jumping once a cell allows a jump at least this long.
constexpr int kResumeJumpCells = 3;
// A tile's jump is the shortest of its 64 cells'; below this the cell's own (longer) jump is
// worth the extra read, above it the ray is in open space anyway.
constexpr int kTrustTileJumpCells = 32;
// Keeps rounding in the distance transform from ever letting a jump touch a blocking cell.
constexpr double kJumpMarginCells = 1e-3;

// Per cell, how many whole cells a ray may advance from any point of the cell: the distance
// transform gives the centre-to-centre distance D to the nearest blocking cell; a point of this
// cell lies within sqrt(2)/2 of its centre and the blocking cell reaches sqrt(2)/2 towards us, so
// D - sqrt(2) is free in every direction. Row-major, kBlocked for blocking cells, else 1 + jump.
cv::Mat clearance_cells(const mapping::OccupancyGrid& grid) {
  cv::Mat free_mask(grid.height(), grid.width(), CV_8UC1);
  for (int y = 0; y < grid.height(); ++y) {
    auto* row = free_mask.ptr<std::uint8_t>(y);
    for (int x = 0; x < grid.width(); ++x) row[x] = grid.is_occupied({x, y}) ? 0 : 255;
  }
  cv::Mat distance_cells;
  cv::distanceTransform(free_mask, distance_cells, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);

  cv::Mat clearance(grid.height(), grid.width(), CV_8UC1);
  for (int y = 0; y < grid.height(); ++y) {
    const auto* distances = distance_cells.ptr<float>(y);
    const auto* free = free_mask.ptr<std::uint8_t>(y);
    auto* out = clearance.ptr<std::uint8_t>(y);
    for (int x = 0; x < grid.width(); ++x) {
      const double jump = std::floor(distances[x] - std::numbers::sqrt2 - kJumpMarginCells);
      out[x] = free[x] == 0
                   ? kBlocked
                   : static_cast<std::uint8_t>(1 + std::clamp(jump, 0.0, 1.0 * kMaxJumpCells));
    }
  }
  return clearance;
}

}  // namespace

// A ray in grid units: cells, measured from the lower-left corner of cell (0, 0).
struct RayCaster::Ray {
  double origin_x = 0.0;
  double origin_y = 0.0;
  double dir_x = 0.0;
  double dir_y = 0.0;
  double inverse_dir_x = 0.0;  // 1 / dir, or 0 along an axis the ray does not move on
  double inverse_dir_y = 0.0;
  double t_start = 0.0;  // where the ray is first inside the grid
  double t_end = 0.0;    // where it leaves the grid or runs out of range

  // Between t_start and t_end the point lies in [0, width] x [0, height] up to rounding, so
  // truncation is floor, and a point on the far edge lands in the padding ring of cells.
  int cell_x(double t) const { return static_cast<int>(origin_x + t * dir_x); }
  int cell_y(double t) const { return static_cast<int>(origin_y + t * dir_y); }
};

// Steps from cell to cell along a ray. A crossing is (boundary - origin) / direction with the
// boundary an exact integer, so a walk seeded mid-ray finds bit-identical crossings to one seeded
// at the start. An axis the ray does not move along has its boundary at infinity.
class RayCaster::CellWalk {
 public:
  CellWalk(const Ray& ray, int start_x, int start_y)
      : x_(start_x),
        y_(start_y),
        step_x_(ray.dir_x > 0.0 ? 1 : -1),
        step_y_(ray.dir_y > 0.0 ? 1 : -1),
        boundary_x_(ray.dir_x == 0.0 ? kInfinity : start_x + (ray.dir_x > 0.0 ? 1.0 : 0.0)),
        boundary_y_(ray.dir_y == 0.0 ? kInfinity : start_y + (ray.dir_y > 0.0 ? 1.0 : 0.0)),
        origin_x_(ray.origin_x),
        origin_y_(ray.origin_y),
        inverse_dir_x_(ray.dir_x == 0.0 ? 1.0 : ray.inverse_dir_x),
        inverse_dir_y_(ray.dir_y == 0.0 ? 1.0 : ray.inverse_dir_y) {}

  // Moves into the next cell and returns the ray parameter where the ray enters it.
  double advance() {
    const double tx = (boundary_x_ - origin_x_) * inverse_dir_x_;
    const double ty = (boundary_y_ - origin_y_) * inverse_dir_y_;
    if (tx < ty) {
      x_ += step_x_;
      boundary_x_ += step_x_;
      return tx;
    }
    y_ += step_y_;
    boundary_y_ += step_y_;
    return ty;
  }

  int x() const { return x_; }
  int y() const { return y_; }

 private:
  int x_;
  int y_;
  int step_x_;
  int step_y_;
  double boundary_x_;
  double boundary_y_;
  double origin_x_;
  double origin_y_;
  double inverse_dir_x_;
  double inverse_dir_y_;
};

RayCaster::RayCaster(const mapping::OccupancyGrid& grid)
    : width_(grid.width()),
      height_(grid.height()),
      tiles_x_((grid.width() + 1 + kTileMask) >> kTileShift),
      resolution_m_(grid.resolution_m()),
      origin_(grid.origin()),
      origin_cos_(std::cos(grid.origin().theta)),
      origin_sin_(std::sin(grid.origin().theta)) {
  // One extra cell on the far sides: see kPadding.
  const int tiles_y = (height_ + 1 + kTileMask) >> kTileShift;
  const auto tiles = static_cast<std::size_t>(tiles_x_) * static_cast<std::size_t>(tiles_y);
  clearance_.assign(tiles << (2 * kTileShift), kPadding);
  tile_jump_.assign(tiles, kMaxJumpCells);
  const cv::Mat clearance = clearance_cells(grid);
  for (int y = 0; y < tiles_y << kTileShift; ++y) {
    for (int x = 0; x < tiles_x_ << kTileShift; ++x) {
      const bool in_grid = x < width_ && y < height_;
      const std::uint8_t value = in_grid ? clearance.at<std::uint8_t>(y, x) : kPadding;
      clearance_[cell_index(x, y)] = value;
      const int jump = value == kBlocked ? 0 : value - 1;
      std::uint8_t& tile_jump = tile_jump_[tile_index(x, y)];
      tile_jump = static_cast<std::uint8_t>(std::min<int>(tile_jump, jump));
    }
  }
}

bool RayCaster::to_grid(geometry::Point2D from, double grid_dir_x, double grid_dir_y,
                        double max_range_m, Ray& ray) const {
  // Into the grid frame, with the origin's rotation precomputed: this runs once per beam.
  const double dx_m = from.x - origin_.x;
  const double dy_m = from.y - origin_.y;
  ray = {(origin_cos_ * dx_m + origin_sin_ * dy_m) / resolution_m_,
         (-origin_sin_ * dx_m + origin_cos_ * dy_m) / resolution_m_,
         grid_dir_x,
         grid_dir_y,
         grid_dir_x == 0.0 ? 0.0 : 1.0 / grid_dir_x,
         grid_dir_y == 0.0 ? 0.0 : 1.0 / grid_dir_y,
         0.0,
         max_range_m / resolution_m_};
  // Slab test against [0, width) x [0, height).
  const auto clip_axis = [&ray](double origin, double dir, double inverse_dir, double size) {
    if (dir == 0.0) {
      if (origin < 0.0 || origin >= size) ray.t_end = -1.0;
      return;
    }
    const double t_a = (0.0 - origin) * inverse_dir;
    const double t_b = (size - origin) * inverse_dir;
    ray.t_start = std::max(ray.t_start, std::min(t_a, t_b));
    ray.t_end = std::min(ray.t_end, std::max(t_a, t_b));
  };
  clip_axis(ray.origin_x, ray.dir_x, ray.inverse_dir_x, width_);
  clip_axis(ray.origin_y, ray.dir_y, ray.inverse_dir_y, height_);
  return ray.t_start <= ray.t_end;
}

double RayCaster::trace(const Ray& ray) const {
  double t = ray.t_start;
  int x = ray.cell_x(t);
  int y = ray.cell_y(t);
  while (true) {
    int jump_cells = tile_jump_at(x, y);
    if (jump_cells < kTrustTileJumpCells) {
      const std::uint8_t clearance = clearance_at(x, y);
      if (clearance == kBlocked) return t;
      jump_cells = clearance - 1;
    }
    if (jump_cells >= kMinJumpCells) {
      t += jump_cells;
      if (t > ray.t_end) return kInfinity;
      x = ray.cell_x(t);
      y = ray.cell_y(t);
      continue;
    }
    CellWalk walk(ray, x, y);
    while (true) {
      t = walk.advance();
      if (t > ray.t_end || !inside(walk.x(), walk.y())) return kInfinity;
      const std::uint8_t clearance = clearance_at(walk.x(), walk.y());
      if (clearance == kBlocked) return t;
      if (clearance > kResumeJumpCells) break;
    }
    x = walk.x();
    y = walk.y();
  }
}

double RayCaster::walk_every_cell(const Ray& ray) const {
  CellWalk walk(ray, ray.cell_x(ray.t_start), ray.cell_y(ray.t_start));
  if (clearance_at(walk.x(), walk.y()) == kBlocked) return ray.t_start;
  while (true) {
    const double t = walk.advance();
    if (t > ray.t_end || !inside(walk.x(), walk.y())) return kInfinity;
    if (clearance_at(walk.x(), walk.y()) == kBlocked) return t;
  }
}

std::optional<double> RayCaster::cast(geometry::Point2D from, double angle_rad,
                                      double max_range_m) const {
  const double grid_angle_rad = angle_rad - origin_.theta;
  Ray ray;
  if (!to_grid(from, std::cos(grid_angle_rad), std::sin(grid_angle_rad), max_range_m, ray)) {
    return std::nullopt;
  }
  const double t = trace(ray);
  if (t == kInfinity) return std::nullopt;
  return t * resolution_m_;
}

void RayCaster::cast_fan(geometry::Point2D from, double first_angle_rad, double increment_rad,
                         double max_range_m, std::span<double> ranges_m) const {
  const double first_grid_angle_rad = first_angle_rad - origin_.theta;
  double dir_x = std::cos(first_grid_angle_rad);
  double dir_y = std::sin(first_grid_angle_rad);
  const double turn_cos = std::cos(increment_rad);
  const double turn_sin = std::sin(increment_rad);
  for (double& range_m : ranges_m) {
    Ray ray;
    range_m =
        to_grid(from, dir_x, dir_y, max_range_m, ray) ? trace(ray) * resolution_m_ : kInfinity;
    // Rotating the direction drifts by about one ulp per beam: nothing over a scan.
    const double next_x = dir_x * turn_cos - dir_y * turn_sin;
    dir_y = dir_x * turn_sin + dir_y * turn_cos;
    dir_x = next_x;
  }
}

std::optional<double> RayCaster::cast_cell_by_cell(geometry::Point2D from, double angle_rad,
                                                   double max_range_m) const {
  const double grid_angle_rad = angle_rad - origin_.theta;
  Ray ray;
  if (!to_grid(from, std::cos(grid_angle_rad), std::sin(grid_angle_rad), max_range_m, ray)) {
    return std::nullopt;
  }
  const double t = walk_every_cell(ray);
  if (t == kInfinity) return std::nullopt;
  return t * resolution_m_;
}

std::optional<double> cast_to_circle(geometry::Point2D from, double angle_rad,
                                     geometry::Point2D center, double radius_m) {
  const double dir_x = std::cos(angle_rad);
  const double dir_y = std::sin(angle_rad);
  const double offset_x = from.x - center.x;
  const double offset_y = from.y - center.y;
  const double along = offset_x * dir_x + offset_y * dir_y;
  const double excess = offset_x * offset_x + offset_y * offset_y - radius_m * radius_m;
  if (excess <= 0.0) return 0.0;
  const double discriminant = along * along - excess;
  if (discriminant < 0.0) return std::nullopt;
  const double t = -along - std::sqrt(discriminant);
  if (t < 0.0) return std::nullopt;
  return t;
}

}  // namespace mobot::sim
