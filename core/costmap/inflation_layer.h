#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/costmap/costmap_layer.h"
#include "core/planning/planning_grid.h"

namespace mobot::costmap {

struct InflationLayerOptions {
  std::string name = "inflation";
  // The robot's inscribed radius: a cell nearer than this to an obstacle is kInscribed (the robot's
  // centre there means a collision). 0.2 m: half the width of a Dashgo D1-sized round base; set it
  // from the footprint (R1's 0.6 x 0.6 m square: 0.3 m).
  double inscribed_radius_m = 0.2;
  // costmap_2d's inflation_radius, measured from the obstacle: beyond the inscribed radius the cost
  // decays out to here, then cells are free. The Dashgo thesis's 0.25 m.
  double inflation_radius_m = 0.25;
  // costmap_2d's cost_scaling_factor, per metre (the Dashgo thesis's 10).
  double cost_scaling_per_m = 10.0;
  // Unknown cells are inflated like obstacles, so paths keep their distance from unexplored space
  // (they stay kUnknown themselves). costmap_2d inflates lethal cells only.
  bool inflate_unknown = false;
};

// costmap_2d's inflation layer with an exact Euclidean distance: every cell gets its distance d to
// the nearest lethal cell (and unknown cell with inflate_unknown) and the cost
//   254 at d = 0, 253 for d <= inscribed, round(252 exp(-k (d - inscribed))) up to the inflation
//   radius, 0 beyond,
// combined with the master by max; unknown cells keep kUnknown. The distance is a two-pass
// transform bounded by the radius: vertical distances per column (capped just past the radius),
// then per row the lower envelope of the parabolas (x - x')^2 + g(x')^2 (Felzenszwalb and
// Huttenlocher) in integer arithmetic, so squared distances are exact integers and the cost comes
// from a table indexed by them. Only the update bounds are written; sources are read from the
// bounds grown by the radius.
class InflationLayer : public CostmapLayer {
 public:
  // Throws std::invalid_argument on negative or non-finite options. An inflation radius at or
  // below the inscribed radius is allowed: there is then no decaying band.
  explicit InflationLayer(const InflationLayerOptions& options = {});

  std::string_view name() const override { return options_.name; }
  const InflationLayerOptions& options() const { return options_; }

  // The inflated cost of a cell at distance_m from the nearest obstacle.
  std::uint8_t cost_at_distance(double distance_m) const;
  // How far (in cells of resolution_m) the layer reads and writes around a change: the inflation
  // radius rounded up, plus one.
  int reach_cells(double resolution_m) const;

  // Inflates `grid` over `bounds` (the planning grid builder calls this on the whole grid).
  void inflate(planning::PlanningGrid& grid, const CellBounds& bounds);

  void match_geometry(const planning::PlanningGrid& master) override;
  void shift(const planning::PlanningGrid& master, int dx_cells, int dy_cells) override;
  // Grows the bounds by the reach: cells that far from a change may change cost.
  void update_bounds(const planning::PlanningGrid& master, CellBounds& bounds) override;
  void update(planning::PlanningGrid& master, const CellBounds& bounds) override;

 private:
  void prepare(double resolution_m);

  InflationLayerOptions options_;
  // Per resolution: the reach and the cost of each squared cell distance up to reach^2.
  double prepared_resolution_m_ = 0.0;
  int reach_ = 0;
  std::vector<std::uint8_t> cost_by_squared_cells_;
  // Scratch reused between updates: vertical distances over the read region, and the envelope.
  std::vector<std::uint16_t> column_cells_;
  std::vector<int> site_x_;
  std::vector<std::int64_t> site_value_;
  std::vector<std::int64_t> boundary_num_;
  std::vector<std::int64_t> boundary_den_;
};

}  // namespace mobot::costmap
