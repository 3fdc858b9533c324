#pragma once

#include <cstddef>
#include <optional>
#include <span>

#include "core/geometry/pose2d.h"
#include "core/slam/probability_grid.h"

namespace mobot::slam {

// One scan of a submap: where its base lies in the map frame, and its points in the base frame.
struct SubmapScan {
  geometry::Pose2D base_in_map;
  std::span<const geometry::Point2D> points_in_base;
};

// An axis-aligned box in the map frame.
struct MapBox {
  double min_x_m = 0.0;
  double min_y_m = 0.0;
  double max_x_m = 0.0;
  double max_y_m = 0.0;
};

struct SubmapOptions {
  // E5: 0.05 m cells.
  double resolution_m = 0.05;
  // The smear of each point (ProbabilityGrid::smear_polyline).
  double sigma_m = 0.07;
  // Consecutive returns of a scan closer than this are one surface and smeared as a segment.
  // 0: points only.
  double max_gap_m = 0.25;
  // Sparser returns of one straight surface (a wall at a grazing angle) are joined up to this gap
  // when their neighbours are collinear within the tolerance (ProbabilityGrid::smear_polyline).
  double max_collinear_gap_m = 1.0;
  double collinear_tolerance_m = 0.05;
};

// docs/algorithms.md E5: a local map of several scans (the recent chain for scan matching, or an
// older node's neighbourhood for loop closure) as one matching field in the map frame. Built anew
// from the scans' current poses, so it always follows the optimised graph. Only the part inside
// `region` is kept: the grid covers just what the scan to be matched can reach.
class Submap {
 public:
  // Throws std::invalid_argument on a non-positive resolution or sigma. An empty submap (no points,
  // or none in the region) has an empty field.
  Submap(std::span<const SubmapScan> scans, const SubmapOptions& options,
         const std::optional<MapBox>& region = std::nullopt);

  const ProbabilityGrid& field() const { return field_; }
  std::size_t point_count() const { return point_count_; }

 private:
  ProbabilityGrid field_;
  std::size_t point_count_ = 0;
};

// The box around points transformed by `pose`, grown by `margin_m`.
MapBox box_around(std::span<const geometry::Point2D> points_in_base, const geometry::Pose2D& pose,
                  double margin_m);

}  // namespace mobot::slam
