#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "core/planning/global_planner.h"
#include "core/planning/planning_grid.h"

namespace mobot::planning {

struct AStarOptions {
  // Entering a cell of cost c costs step_length * (1 + cost_penalty_weight * c / 252): paths trade
  // up to (1 + weight) times their length for clearance. 0 gives shortest paths.
  double cost_penalty_weight = 3.0;
  // A start inside the inflated zone (the robot touching an inflated wall, or a localisation jump)
  // escapes to the nearest traversable cell within this distance instead of failing.
  double max_escape_distance_m = 0.5;
};

// ALGORITHMS.md C1: A* on the planning grid, 8-connected, octile heuristic, no corner cutting (a
// diagonal step needs both side cells traversable). The heuristic is the octile distance in metres,
// which never overestimates because every step costs at least its length, so paths are optimal for
// the cost model above. Flat arrays and a 4-ary heap keep a 1000 x 1000 search in tens of ms.
//
// Start in an obstacle: when the start cell is not traversable (cost >= 253), the planner runs a
// small Dijkstra through inscribed (and unknown) cells, and through lethal cells only if the start
// itself is lethal, to the nearest traversable cell within max_escape_distance_m, and plans from
// there; the escape cells begin the returned path and start_escaped is set. Users expect a robot
// that ended up touching an inflated wall to drive away from it, not to refuse every goal.
class AStarPlanner : public GlobalPlanner {
 public:
  // Throws std::invalid_argument on negative or non-finite options.
  explicit AStarPlanner(const AStarOptions& options = {});

  std::string_view name() const override { return "astar"; }
  PlanResult plan(const PlanningGrid& grid, const geometry::Pose2D& start,
                  const geometry::Pose2D& goal) override;

  const AStarOptions& options() const { return options_; }
  // The cost of entering a cell of the given cost per metre of step (exposed for tests).
  double step_multiplier(std::uint8_t cost) const { return multiplier_[cost]; }

 private:
  // Per-cell search state packed in one 16-byte record, so a neighbour check touches one cache
  // line besides the cost byte. A cell's record is valid only when its stamp matches the current
  // search's, so no 1e6-cell reset is needed between plans.
  struct CellState {
    double g;
    std::int32_t parent;
    std::uint32_t stamp;  // (search number << 1) | closed
  };
  // f and h are non-negative, so their IEEE bit patterns order like their values: the heap
  // compares integers, which the compiler turns into conditional moves instead of unpredictable
  // branches (about 10 % of a maze search).
  struct HeapNode {
    std::uint64_t f;  // bits of the double f = g + h
    std::uint32_t h;  // bits of the float h; a tie-break only, so optimality does not depend on it
    std::uint32_t index;
  };

  static HeapNode make_node(double f, double h, std::uint32_t index);
  void begin_search(std::size_t cell_count);
  // Cells from the start to the nearest traversable cell, or nullopt when none is within reach.
  std::optional<std::vector<mapping::CellIndex>> escape(const PlanningGrid& grid,
                                                        mapping::CellIndex start) const;
  // Fills `result.cells` and `result.cost`; false when the goal is unreachable.
  bool search(const PlanningGrid& grid, mapping::CellIndex start, mapping::CellIndex goal,
              PlanResult& result);

  AStarOptions options_;
  std::array<double, 256> multiplier_{};
  std::vector<CellState> state_;
  std::uint32_t search_number_ = 0;
  std::vector<HeapNode> heap_;
};

}  // namespace mobot::planning
