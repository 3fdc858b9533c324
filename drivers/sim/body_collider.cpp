#include "drivers/sim/body_collider.h"

#include <cmath>

namespace mobot::sim {

BodyCollider::BodyCollider(const World& world, double footprint_length_m,
                           double footprint_width_m, double height_m)
    : floor_(world.floor),
      half_length_m_(footprint_length_m / 2.0),
      half_width_m_(footprint_width_m / 2.0) {
  for (const Box3D& box : world.boxes) {
    if (box.min_z_m < height_m && box.max_z_m > 0.0) boxes_.push_back(box);
  }
}

OrientedRect BodyCollider::footprint_at(const geometry::Pose2D& pose) const {
  return {pose, half_length_m_, half_width_m_};
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
  const geometry::Pose2D local_center = geometry::compose(geometry::inverse(floor_.origin()),
                                                          footprint.center);
  const OrientedRect local{local_center, footprint.half_length_m, footprint.half_width_m};
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

}  // namespace mobot::sim
