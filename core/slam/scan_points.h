#pragma once

#include <vector>

#include "core/geometry/pose2d.h"
#include "core/msgs/laser_scan.h"

namespace mobot::slam {

struct ScanPointsOptions {
  // E5: gmapping's maxUrange on the Dashgo, 8 m: returns beyond it are too sparse and too noisy
  // (angular error grows with range) to help matching.
  double max_range_m = 8.0;
  // Returns closer than this are the robot itself or dust on the window.
  double min_range_m = 0.05;
  // Edge of the voxel filter's square cells; one point (the centroid) is kept per cell. 0: off.
  double voxel_size_m = 0.0;
};

// A laser scan's returns as points in the base frame, plus the sensor's origin in the base frame
// (rays for free space start there). Beams with no return (out of [range_min, range_max], beyond
// max_range_m, NaN/inf) are not points; `misses` keeps the directions of beams that saw nothing
// within max_range_m so a renderer can still clear space along them.
struct ScanPoints {
  geometry::Point2D sensor_origin_in_base;
  std::vector<geometry::Point2D> points_in_base;
  // Ends of rays that returned nothing within max_range_m, at max_range_m (free space only).
  std::vector<geometry::Point2D> misses_in_base;
};

// Throws std::invalid_argument on negative or non-finite options or min_range_m > max_range_m.
ScanPoints scan_to_points(const msgs::LaserScan& scan, const ScanPointsOptions& options = {});

// The voxel filter alone: one centroid per occupied square of `voxel_size_m` (<= 0: unchanged),
// in a deterministic order.
std::vector<geometry::Point2D> voxel_filter(const std::vector<geometry::Point2D>& points,
                                            double voxel_size_m);

}  // namespace mobot::slam
