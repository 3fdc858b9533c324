#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"
#include "core/perception/point_cloud.h"

namespace mobot::perception {

// docs/algorithms.md P2, "image pressure and barrier detection": a 3D cloud becomes the 2D obstacle
// map of what the robot would hit.
struct IpabdOptions {
  // Step 1: points higher than the robot pass over it; points within the tolerance of the floor
  // are the floor. Points below -tolerance stay: a drop is an obstacle too.
  double robot_height_m = 1.2;
  double floor_tolerance_m = 0.05;
  // Step 2: bearing bins around the sweep's origin, and how far the map reaches (the experiment's
  // 40 x 40 cells of 0.2 m reach 4 m each way).
  double bearing_step_rad = 0.0087266462599716477;  // 0.5 deg
  double max_range_m = 8.0;
  // Step 3 (PDBS): consecutive bearings belong to one segment unless their ranges differ by more
  // than c0 + c1 * min(r_i, r_i+1). Within a segment the cells between neighbouring points are
  // occupied too, so a wall far away stays a barrier although its points are sparse.
  bool segment = true;
  double pdbs_c0_m = 0.1;
  double pdbs_c1 = 0.05;
  // Step 4: the grid's cell is robot_diameter_m / 3; the IPaBD map is dilated by the robot radius.
  double robot_diameter_m = 0.6;
  double dilation_radius_m = 0.3;
  // When set, the grid's cell corners lie on this lattice (origin + k * cell), so the result copies
  // cell for cell into a layer that uses the same lattice.
  std::optional<geometry::Point2D> lattice_origin;

  double cell_m() const { return robot_diameter_m / 3.0; }
};

struct IpabdSegment {
  std::size_t first_bin = 0;  // index into IpabdResult::bins
  std::size_t bins = 0;
};

struct IpabdResult {
  // kOccupied where a kept point lies (or a segment passes), kFree where the sweep saw floor or
  // space up to the first obstacle, kUnknown where it saw nothing.
  mapping::OccupancyGrid obstacles;
  // The IPaBD map proper: obstacles dilated by the robot radius (kOccupied), other cells as above.
  mapping::OccupancyGrid dilated;
  // Step 2's nearest point per bearing bin that holds one, in bearing order.
  struct Bin {
    std::size_t index = 0;  // bearing = -pi + (index + 0.5) * bearing_step_rad
    float range_m = 0.0F;
    geometry::Point2D point_in_map;
  };
  std::vector<Bin> bins;
  std::vector<IpabdSegment> segments;
  std::size_t points_in = 0;
  std::size_t points_above = 0;  // dropped by step 1: above the robot
  std::size_t points_floor = 0;  // dropped by step 1: floor
  std::size_t points_out_of_range = 0;
};

// Runs P2 on a cloud in the map frame around `origin_in_map` (where the sensor stood). Throws
// std::invalid_argument on non-positive or non-finite options.
IpabdResult run_ipabd(std::span<const CloudPoint> cloud, geometry::Point2D origin_in_map,
                      const IpabdOptions& options = {});

}  // namespace mobot::perception
