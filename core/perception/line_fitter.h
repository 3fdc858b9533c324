#pragma once

#include <span>

#include "core/geometry/pose2d.h"
#include "core/perception/line_segment.h"

namespace mobot::perception {

// Total-least-squares line through a growing set of points: the line that minimises the sum of
// squared perpendicular distances. Keeps running sums, so adding a point and refitting are O(1),
// which is what region growing over a scan needs.
class LineFitter {
 public:
  void add(const geometry::Point2D& point);
  void clear();
  int count() const { return count_; }

  // Normalised Hessian parameters of the best line (no endpoints, no covariance). Meaningless
  // for fewer than two distinct points.
  LineSegment fit() const;

 private:
  // Sums are taken relative to the first point so that far-away points do not cancel digits.
  geometry::Point2D reference_;
  int count_ = 0;
  double sum_x_ = 0.0;
  double sum_y_ = 0.0;
  double sum_xx_ = 0.0;
  double sum_xy_ = 0.0;
  double sum_yy_ = 0.0;
};

// Covariance of (rho, alpha) of the total-least-squares line through `points`, each with its own
// variance perpendicular to the line: the first-order propagation of every point's error through
// the (unweighted) fit, as Arras & Siegwart derive it, written as the sandwich A^-1 B A^-1 of the
// residual Jacobians. When the points scatter more than their variances allow (a rough wall, an
// underestimated sensor noise), it is inflated by the reduced chi-square, so it never claims more
// than the scatter supports. Returns the line with its covariance set; the covariance stays
// untouched for fewer than three points or points that do not span a line.
LineSegment with_covariance(LineSegment line, std::span<const geometry::Point2D> points,
                            std::span<const double> perpendicular_var_m2);

}  // namespace mobot::perception
