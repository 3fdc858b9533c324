#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <span>

#include "core/geometry/pose2d.h"

namespace mobot::planning {

// A forward path made of up to three pieces of constant curvature, each leaving where and along
// the heading the previous one ended: the shape of Dubins' shortest paths for a car that turns no
// tighter than a given radius (Dubins 1957), of a single arc, and of a Hybrid A* motion primitive.
class DubinsPath {
 public:
  struct Piece {
    double curvature_1pm = 0.0;  // > 0 turns left, 0 is straight
    double length_m = 0.0;       // >= 0
  };

  DubinsPath() = default;
  // Throws std::invalid_argument on more than three pieces or a negative length.
  DubinsPath(const geometry::Pose2D& start, std::span<const Piece> pieces);

  const geometry::Pose2D& start() const { return start_; }
  std::span<const Piece> pieces() const { return {pieces_.data(), count_}; }
  double length_m() const;
  // The pose after driving s_m along the path, s_m clamped to [0, length_m()]. The heading is
  // start.theta plus the turning so far, not wrapped, so it keeps counting whole turns.
  geometry::Pose2D pose_at(double s_m) const;
  geometry::Pose2D end() const { return pose_at(length_m()); }
  // The largest |curvature| of its pieces that have a length.
  double max_curvature_1pm() const;

 private:
  geometry::Pose2D start_;
  std::array<Piece, 3> pieces_{};
  std::size_t count_ = 0;
};

// The pose reached from `pose` by driving length_m forward on a constant curvature (exact, not
// integrated). The heading is not wrapped.
geometry::Pose2D advance(const geometry::Pose2D& pose, double curvature_1pm, double length_m);

// The shortest forward path from `start` to `goal` (position and heading) whose curvature never
// exceeds 1 / radius_m: the best of Dubins' six words LSL, RSR, LSR, RSL, RLR, LRL, with the
// closed forms of Shkel and Lumelsky (2001). Always exists. radius_m must be positive.
DubinsPath shortest_dubins_path(const geometry::Pose2D& start, const geometry::Pose2D& goal,
                                double radius_m);

// The shorter of the two turn-then-straight paths (LS, RS) from `start` to `point` arriving with
// any heading, on circles of radius_m. One of them always exists: a point inside the left turning
// circle is reached by turning right first, and the other way round. This is the shortest path to
// a point except when the point lies inside a turning circle, where a two-turn path can be shorter
// (Bui, Boissonnat, Soueres, Laumond 1994), so as a distance it may overestimate there.
DubinsPath turn_then_straight_to_point(const geometry::Pose2D& start, geometry::Point2D point,
                                       double radius_m);

// The single arc (a straight line when the point lies dead ahead) that leaves `start` along its
// heading and passes through `point`, when the point lies ahead (turning by less than a half turn)
// and the arc's radius is at least min_radius_m; else nullopt. It reaches points close ahead and
// a little aside that every path of minimum radius would have to loop around to reach.
std::optional<DubinsPath> arc_to_point(const geometry::Pose2D& start, geometry::Point2D point,
                                       double min_radius_m);

}  // namespace mobot::planning
