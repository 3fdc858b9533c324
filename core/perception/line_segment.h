#pragma once

#include <vector>

#include "core/geometry/pose2d.h"

namespace mobot::perception {

// A straight wall segment in Hessian normal form, x cos(alpha) + y sin(alpha) = rho, in whichever
// frame the holder names. rho_m >= 0 is the distance of the line from that frame's origin and
// alpha_rad in (-pi, pi] the direction of the normal pointing from the origin to the line.
// The covariance is that of (rho_m, alpha_rad).
struct LineSegment {
  double rho_m = 0.0;
  double alpha_rad = 0.0;
  // Endpoints lie on the line; meaningful only when has_endpoints (an infinite line otherwise).
  geometry::Point2D start;
  geometry::Point2D end;
  bool has_endpoints = true;
  double var_rho_m2 = 0.0;
  double var_alpha_rad2 = 0.0;
  double cov_rho_alpha_m_rad = 0.0;
  // How many scan points or grid cells support the fit (0 when unknown).
  int point_count = 0;
  // The side of a wall face that is free space, so a sensor can only see the face from there:
  // +1 away from the frame's origin (signed_distance > 0), -1 toward it, 0 unknown (a line fitted
  // to a scan). Map faces have it; it tells apart the two faces of a thin wall, whose lines are
  // parallel and a wall's thickness apart.
  int free_side = 0;

  double length_m() const;
};

// True when every parameter (and the endpoints, when present) is finite and rho_m >= 0.
bool is_valid(const LineSegment& line);

// Brings (rho, alpha) into the canonical form rho >= 0, alpha in (-pi, pi]. Flipping the sign of
// rho negates the rho-alpha covariance and the free side.
LineSegment normalized(LineSegment line);

// A line given in the frame of `frame`, returned in frame's parent, with its covariance
// propagated to first order (the frame itself is taken as exact).
LineSegment transform_line(const geometry::Pose2D& frame, const LineSegment& line);

// Distance of a point from the infinite line, signed positive on the side away from the origin.
double signed_distance(const LineSegment& line, const geometry::Point2D& point);

// The foot of the perpendicular from a point to the infinite line.
geometry::Point2D project_onto(const LineSegment& line, const geometry::Point2D& point);

}  // namespace mobot::perception
