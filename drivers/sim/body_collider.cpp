#include "drivers/sim/body_collider.h"

#include <cmath>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace mobot::sim {
namespace {

std::vector<float> wall_distances(const mapping::OccupancyGrid& floor) {
  cv::Mat free_mask(floor.height() + 2, floor.width() + 2, CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < floor.height(); ++y) {
    auto* row = free_mask.ptr<std::uint8_t>(y + 1);
    for (int x = 0; x < floor.width(); ++x) row[x + 1] = floor.is_occupied({x, y}) ? 0 : 255;
  }
  cv::Mat distances;
  cv::distanceTransform(free_mask, distances, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  return {distances.begin<float>(), distances.end<float>()};
}

}  // namespace

BodyCollider::BodyCollider(const World& world, double footprint_length_m, double footprint_width_m,
                           double height_m, double offset_m)
    : floor_(world.floor),
      half_length_m_(footprint_length_m / 2.0),
      half_width_m_(footprint_width_m / 2.0),
      offset_m_(offset_m),
      wall_distance_cells_(wall_distances(world.floor)),
      half_diagonal_m_(std::hypot(half_length_m_, half_width_m_)) {
  for (const Box3D& box : world.boxes) {
    if (box.min_z_m < height_m && box.max_z_m > 0.0) boxes_.push_back(box);
  }
}

OrientedRect BodyCollider::footprint_at(const geometry::Pose2D& pose) const {
  return {geometry::compose(pose, {offset_m_, 0.0, 0.0}), half_length_m_, half_width_m_};
}

std::optional<std::string> BodyCollider::contact(const geometry::Pose2D& pose) const {
  const OrientedRect footprint = footprint_at(pose);
  for (const Box3D& box : boxes_) {
    if (overlaps(footprint, {box.min_x_m, box.min_y_m, box.max_x_m, box.max_y_m})) {
      return box.name;
    }
  }
  if (touches_wall(footprint)) return "wall";
  return std::nullopt;
}

bool BodyCollider::touches_wall(const OrientedRect& footprint) const {
  // Work in the grid's frame, where cells are axis-aligned squares of one resolution.
  const double resolution_m = floor_.resolution_m();
  const geometry::Pose2D local_center =
      geometry::compose(geometry::inverse(floor_.origin()), footprint.center);
  const OrientedRect local{local_center, footprint.half_length_m, footprint.half_width_m};
  const int center_x = static_cast<int>(std::floor(local_center.x / resolution_m));
  const int center_y = static_cast<int>(std::floor(local_center.y / resolution_m));
  if (clear_of_walls(center_x, center_y)) return false;
  const AxisAlignedRect bounds = bounding_box(local);
  const int min_x = static_cast<int>(std::floor(bounds.min_x_m / resolution_m));
  const int min_y = static_cast<int>(std::floor(bounds.min_y_m / resolution_m));
  const int max_x = static_cast<int>(std::floor(bounds.max_x_m / resolution_m));
  const int max_y = static_cast<int>(std::floor(bounds.max_y_m / resolution_m));
  for (int y = min_y; y <= max_y; ++y) {
    for (int x = min_x; x <= max_x; ++x) {
      const mapping::CellIndex cell{x, y};
      // Beyond the floor plan there is no floor to stand on: treat it as wall.
      if (floor_.contains(cell) && !floor_.is_occupied(cell)) continue;
      const AxisAlignedRect square{x * resolution_m, y * resolution_m, (x + 1) * resolution_m,
                                   (y + 1) * resolution_m};
      if (overlaps(local, square)) return true;
    }
  }
  return false;
}

bool BodyCollider::clear_of_walls(int x, int y) const {
  const int padded_width = floor_.width() + 2;
  if (x < -1 || y < -1 || x > floor_.width() || y > floor_.height()) return false;
  const float distance_cells = wall_distance_cells_[static_cast<std::size_t>(y + 1) *
                                                        static_cast<std::size_t>(padded_width) +
                                                    static_cast<std::size_t>(x + 1)];
  // A point of this cell is within sqrt(2)/2 cells of its centre, and so is every point of a wall
  // cell of its own centre.
  return (distance_cells - std::numbers::sqrt2) * floor_.resolution_m() > half_diagonal_m_;
}

}  // namespace mobot::sim
