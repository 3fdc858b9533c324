#pragma once

#include <cmath>

namespace mobot::geometry {

// A planar pose in metres and radians (counter-clockwise), in whichever frame the holder names.
struct Pose2D {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;

  bool operator==(const Pose2D&) const = default;
};

struct Point2D {
  double x = 0.0;
  double y = 0.0;

  bool operator==(const Point2D&) const = default;
};

// Wraps an angle into (-pi, pi].
double wrap_angle(double angle_rad);

// a (+) b: b expressed in a's frame, returned in a's parent frame.
Pose2D compose(const Pose2D& a, const Pose2D& b);

// The pose that undoes `a`: compose(a, inverse(a)) is the identity.
Pose2D inverse(const Pose2D& a);

// A point given in the frame of `frame`, returned in frame's parent.
Point2D transform_point(const Pose2D& frame, const Point2D& point);

bool is_finite(const Pose2D& pose);

double distance_m(const Point2D& a, const Point2D& b);

}  // namespace mobot::geometry
