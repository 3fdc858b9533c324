#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "core/geometry/pose2d.h"

namespace mobot::slam {

// Where a grid lies: the map-frame position of the lower-left corner of cell (0, 0), the cell
// edge, and the size. Cell (x, y) covers [origin + x * res, origin + (x + 1) * res).
struct GridLimits {
  double origin_x_m = 0.0;
  double origin_y_m = 0.0;
  double resolution_m = 0.05;
  int width = 0;
  int height = 0;

  // The smallest limits whose cells cover every point plus `margin_m` on each side; empty (0 x 0)
  // for no points. Throws std::invalid_argument on a non-positive resolution.
  static GridLimits covering(std::span<const geometry::Point2D> points, double resolution_m,
                             double margin_m);
  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
  // Continuous cell coordinates of a map point: cell (x, y)'s centre is at (x, y).
  double to_cell_x(double x_m) const { return (x_m - origin_x_m) / resolution_m - 0.5; }
  double to_cell_y(double y_m) const { return (y_m - origin_y_m) / resolution_m - 0.5; }
};

// A grid of occupancy probabilities in [0, 1] (0 = certainly free or never seen, 1 = a wall
// exactly here), Cartographer-style float cells. As the matching field of docs/algorithms.md E5
// every scan point raises the cells around it to a Gaussian of their distance (Karto's smear):
// the field is 1 on a point and decays over sigma, which gives correlative matching a tolerant
// score and Gauss-Newton a smooth slope.
class ProbabilityGrid {
 public:
  ProbabilityGrid() = default;
  // All cells 0. Throws std::invalid_argument on negative sizes or a non-positive resolution.
  explicit ProbabilityGrid(const GridLimits& limits);

  const GridLimits& limits() const { return limits_; }
  int width() const { return limits_.width; }
  int height() const { return limits_.height; }
  bool empty() const { return cells_.empty(); }

  // 0 outside the grid: unseen space neither attracts nor repels a scan.
  float at(int x, int y) const { return limits_.contains(x, y) ? cells_[index(x, y)] : 0.0F; }
  void set(int x, int y, float probability) {
    if (limits_.contains(x, y)) cells_[index(x, y)] = probability;
  }
  const std::vector<float>& cells() const { return cells_; }

  // Raises every cell within 3 sigma of each point to max(cell, exp(-d^2 / (2 sigma^2))), d the
  // distance from the cell's centre to the point. Non-finite points are skipped. Throws
  // std::invalid_argument on a non-positive sigma.
  void smear_points(std::span<const geometry::Point2D> points_in_map, double sigma_m);

  // Like smear_points, but consecutive points closer than `max_gap_m` (neighbouring beams on one
  // surface) are joined and the distance is to the segment between them: a wall seen with beams
  // 14 cm apart (1 deg at 8 m) becomes one even ridge instead of a row of bumps that would pull a
  // matched scan's points into the dips between them.
  //
  // A wall seen at a grazing angle is sampled far more sparsely (beams 0.3 m apart at 6 m along a
  // wall 1 m away), and where those samples fall depends on where the sensor stood: left as bumps
  // they pull a scan taken further on back towards that spot (a corridor's map then lags the
  // robot). So consecutive points up to `max_collinear_gap_m` apart are joined too when each lies
  // within `collinear_tolerance_m` of the line through the other and its outer neighbour: the
  // same straight surface. A beam passing a door jamb into the room behind is not collinear.
  // Throws std::invalid_argument on a non-positive sigma or negative gaps or tolerance.
  void smear_polyline(std::span<const geometry::Point2D> points_in_map, double sigma_m,
                      double max_gap_m, double max_collinear_gap_m = 0.0,
                      double collinear_tolerance_m = 0.0);

  // The field value at a map point by bicubic (Catmull-Rom) interpolation of the cell centres, and
  // its gradient in 1/m: what Gauss-Newton needs (docs/algorithms.md E5, the refiner).
  struct Sample {
    double value = 0.0;
    double d_dx = 0.0;
    double d_dy = 0.0;
  };
  Sample interpolate(double x_m, double y_m) const;

 private:
  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(limits_.width) +
           static_cast<std::size_t>(x);
  }

  GridLimits limits_;
  std::vector<float> cells_;
};

}  // namespace mobot::slam
