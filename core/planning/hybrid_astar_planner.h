#pragma once

#include <cstddef>
#include <memory>
#include <numbers>
#include <string_view>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/planning/global_planner.h"
#include "core/planning/planning_grid.h"

namespace mobot::planning {

struct HybridAStarOptions {
  // The tightest turn the base can drive; R3's tricycles: wheelbase 1.844 m / tan(pi / 4).
  double min_turning_radius_m = 1.844;
  // Length of one motion primitive, rounded so that a full-lock primitive turns a whole number of
  // heading bins (at least one): headings then stay exactly on the bins, as in Nav2's smac
  // planner. 0.5 m at R = 1.844 m gives 0.483 m, three 5 degree bins per full-lock step.
  double primitive_length_m = 0.5;
  // Steering samples per side: 1 gives full left, straight, full right; n adds n - 1 gentler
  // turns per side (each rounded to a whole number of bins, duplicates dropped).
  int steering_samples_per_side = 1;
  int heading_bins = 72;
  // The spatial cell of a search state (Dolgov's 3D grid): two nodes in the same state cell and
  // heading bin are one node, the cheaper kept. Must be smaller than the primitive length, so a
  // straight step always leaves its cell. Finer cells find tighter manoeuvres, coarser ones prune
  // more and expand fewer nodes (hybrid_astar_bench.cpp measures both).
  double state_cell_m = 0.1;
  // As AStarOptions: a primitive costs its length times 1 + weight * cost / 252, with the cost the
  // highest under the body's check points along it, so paths keep the whole body off walls.
  double cost_penalty_weight = 3.0;
  // A step's cost is further multiplied by 1 + steering_penalty * (its curvature times R: 1 at
  // full lock) + steering_change_penalty when it turns against the previous step's turn: fewer,
  // longer turns, and no slalom on open ground, which pure pursuit tracks badly.
  double steering_penalty = 0.1;
  double steering_change_penalty = 0.3;
  // The search gives up (kNoPath) after this many expansions, so a goal the body cannot reach
  // (a corridor too narrow to turn into) fails in bounded time; hybrid_astar_bench.cpp measures
  // what it costs.
  std::size_t max_expansions = 100000;

  // The body: a rectangle footprint_length_m x footprint_width_m whose centre lies
  // footprint_offset_m ahead of the base origin (the rear-axle centre of a tricycle), on a grid
  // inflated with inscribed_radius_m (navigation.inscribed_radius_m). Defaults: R3's tricycle,
  // 2.64 x 1.2 m reaching 2.24 m ahead and 0.4 m behind the rear axle, on the 0.8 m inflation of
  // deploy/config/tricycle_*.yaml. A zero length or width checks the base origin alone, like the
  // grid planners (the inflation then has to cover the whole body); so does a body that lies
  // within the inscribed radius of its origin (see check_points).
  double footprint_length_m = 2.64;
  double footprint_width_m = 1.2;
  double footprint_offset_m = 0.92;
  double inscribed_radius_m = 0.8;
  // A pose is checked at least every time the body's farthest check point moved this far; the
  // check points' cover radius is shrunk by half of it (see footprint_check_points).
  double collision_step_m = 0.1;
  // Spacing of the returned points.
  double path_step_m = 0.1;

  // Analytic expansion (Dolgov's "Reeds-Shepp shot", here forward-only Dubins): a collision-free
  // curve from the node being expanded to the goal ends the search. Tried on the first expansion,
  // every shot_interval expansions, and at every expansion within shot_always_within_m of the
  // goal, for curves up to max_shot_length_m long (a long shot would cut across costly ground the
  // search is there to weigh, as Nav2's analytic_expansion_max_length says).
  int shot_interval = 10;
  double shot_always_within_m = 4.0;
  double max_shot_length_m = 12.0;

  // The goal's heading is kept within this; pi (the default) takes the goal as a position and
  // the body may arrive with any heading (a Pose2D cannot say that a goal has no heading).
  double goal_heading_tolerance_rad = std::numbers::pi;
  // With a free heading, arrive only with one the body can leave by, forward as it came: a
  // straight run of two turning radii, or a half turn at full lock to either side, clear of the
  // inflated zone. A base that cannot reverse would otherwise park nose to a wall, or at the end
  // of a dead end, and find no path to any next goal. A goal it could reach only that way is
  // refused (kNoPath) rather than left as a trap.
  bool keep_way_out = true;
  // A start whose body touches the inflated zone (the robot stopped close to a wall, or a
  // localisation jump) may drive this far with its check points in the inscribed band, never on
  // an obstacle, unknown cell or off the grid; the path's later poses must be clear. Longer than
  // the grid planners' 0.5 m: a car leaves a wall by turning away, and at R = 1.844 m its body
  // needs one to two metres for that. The start cell's own escape (grid_search.h) uses it too.
  double max_escape_distance_m = 2.0;
};

// The check points, in the base frame, of a length_m x width_m rectangle centred offset_m ahead
// of the base origin: the base origin, then a grid of points whose discs of radius cover_radius_m
// cover the rectangle (the fewest points over the possible numbers of rows). When every point lies
// at least cover_radius_m from any obstacle, so does the whole body. A zero length or width gives
// the origin alone. Throws std::invalid_argument on a non-positive cover radius or a negative or
// non-finite size.
std::vector<geometry::Point2D> footprint_check_points(double length_m, double width_m,
                                                      double offset_m, double cover_radius_m);

// A car-like global planner: Hybrid A* (Dolgov, Thrun, Montemerlo, Diebel 2008), forward only.
// The search runs over (x, y, heading) states binned into state_cell_m cells and heading_bins
// headings; each expansion drives the node's continuous pose along arcs of constant curvature
// (full left, straight, full right and optionally gentler turns) no tighter than
// min_turning_radius_m, so every path is drivable by a car that cannot turn on the spot or
// reverse. A pose collides when any of the body's check points (footprint_check_points) lies on a
// cell of cost >= kInscribed or off the grid: the inflation then covers the body's width.
//
// Heuristic: the larger of (1) the obstacle-free non-holonomic distance (the turn-then-straight
// distance to the goal point, or the Dubins distance when the goal heading is held tighter than
// half a bin) and (2) the holonomic distance with obstacles: a Dijkstra from the goal over the
// traversable cells with the same cost weighting, computed once per plan, which steers the search
// out of dead ends it would otherwise fill. A start the Dijkstra does not reach fails at once.
//
// The search ends with an analytic expansion: from an expanded node, the shortest of the curves
// to the goal (a single arc, a turn then a straight, and for a held heading the Dubins paths to
// it and to the tolerance's edges), ending within the heading tolerance, collision free and no
// longer than max_shot_length_m; the three shortest are checked.
//
// Result: points_in_map samples the path every path_step_m or less, from the exact start pose
// (leaving along its heading) to the exact goal; its curvature never exceeds
// 1 / min_turning_radius_m. cells are the cells those points' polyline crosses, 8-connected,
// without repeats; cost is the penalised length (primitives and shot); expanded_cells counts the
// expanded states. Errors: search_ends' (grid_search.h) in its order, then kGoalInObstacle when
// the body fits at the goal at no heading the tolerance allows, kStartInObstacle when the
// escape reached no pose whose body is clear, kNoPath when the search ran out of nodes or
// expansions. A goal in the start's cell is reached by a two-point path when the heading allows.
class HybridAStarPlanner : public GlobalPlanner {
 public:
  // Throws std::invalid_argument on invalid options (non-positive radius, primitive, state cell,
  // steps or bins; negative penalties or sizes; a state cell not below the primitive length).
  explicit HybridAStarPlanner(const HybridAStarOptions& options = {});
  ~HybridAStarPlanner() override;
  HybridAStarPlanner(HybridAStarPlanner&&) noexcept;
  HybridAStarPlanner& operator=(HybridAStarPlanner&&) noexcept;

  std::string_view name() const override { return "hybrid_astar"; }
  // A shortcut smoother would replace the arcs by chords and corners: the curvature bound would
  // be lost, and with it the path's point.
  bool route_may_be_smoothed() const override { return false; }
  PlanResult plan(const PlanningGrid& grid, const geometry::Pose2D& start,
                  const geometry::Pose2D& goal) override;

  const HybridAStarOptions& options() const { return options_; }
  // The body's check points on a grid of this resolution: the cover radius is the inscribed
  // radius less a cell's diagonal (a check point and an obstacle each lie anywhere in their
  // cells) and half the collision step.
  std::vector<geometry::Point2D> check_points(double resolution_m) const;
  // The primitive length after the rounding described at primitive_length_m.
  double primitive_length_m() const;

 private:
  struct Workspace;  // search state kept between plans (hybrid_astar_planner.cpp)

  HybridAStarOptions options_;
  std::unique_ptr<Workspace> workspace_;
};

}  // namespace mobot::planning
