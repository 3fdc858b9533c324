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

// docs/algorithms.md C1: A* on the planning grid, 8-connected, octile heuristic, no corner cutting
// (a diagonal step needs both side cells traversable). The heuristic is the octile distance in
// metres, which never overestimates because every step costs at least its length, so paths are
// optimal for the cost model above. A bucketed open list and 10 bytes of search state per cell in
// flat arrays keep a search through a 1000 x 1000 maze within the 50 ms target (see
// astar_planner.cpp).
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
  // Per-cell search state lives in two flat arrays, g_ (double) and stamp_, 10 bytes a cell (a
  // 16-byte record with a parent index was measured slower: more cache misses). A stamp is
  // (search number << 4) | (closed << 3) | step, where step indexes the step table and says how
  // the cell was last reached, which is all the path reconstruction needs. A cell's g and step are
  // valid only while its stamp holds the current search number, so no per-plan reset of 1e6 cells.
  using Stamp = std::uint16_t;
  static constexpr unsigned kStepBits = 3;
  static constexpr unsigned kMaxSearchNumber = 0xFFFFU >> (kStepBits + 1);

  // f and h are non-negative, so their IEEE bit patterns order like their values and the open
  // list compares integers, which the compiler turns into conditional moves.
  struct HeapNode {
    std::uint64_t f;  // bits of the double f = g + h: the exact key
    std::uint32_t h;  // bits of the float h; a tie-break only, so optimality does not depend on it
    std::uint32_t index;
  };

  // The open list: a ring of buckets of f, each a fraction of a cell step wide; the bucket being
  // popped from is sorted, the later ones are filled unordered. Pops in exact (f, h) order, like
  // a heap (astar_planner.cpp explains why this is exact and why the ring is wide enough).
  class OpenList {
   public:
    // Empties the list for a search whose first key is f_start and whose open keys never spread
    // more than `span` above the smallest one; `resolution` (the cell size) sets bucket widths.
    void reset(double f_start, double span, double resolution);
    bool empty() const { return size_ == 0; }
    void push(double f, double h, std::uint32_t index);
    HeapNode pop();

   private:
    // The ring of buckets; the current one is sorted, largest first.
    std::vector<std::vector<HeapNode>> buckets_;
    std::vector<HeapNode> late_;           // a 4-ary heap: nodes pushed into the current bucket
    std::vector<std::uint64_t> occupied_;  // one bit per bucket of the ring: not empty
    std::size_t mask_ = 0;                 // bucket count - 1 (a power of two)
    std::int64_t current_ = 0;             // absolute number of the bucket being popped from
    double f_start_ = 0.0;
    double inverse_width_ = 1.0;
    std::size_t size_ = 0;
  };

  static HeapNode make_node(double f, double h, std::uint32_t index);
  // Advances the search number (resetting the stamps when it runs out or the grid size changed)
  // and fills the step cost tables for the grid's resolution.
  void begin_search(std::size_t cell_count, double resolution);
  // Fills `result.cells` and `result.cost`; false when the goal is unreachable.
  bool search(const PlanningGrid& grid, mapping::CellIndex start, mapping::CellIndex goal,
              PlanResult& result);

  AStarOptions options_;
  std::array<double, 256> multiplier_{};
  std::vector<double> g_;
  std::vector<Stamp> stamp_;
  unsigned search_number_ = 0;
  OpenList open_;
  // The cost of a straight and of a diagonal step into a cell of each cost, at step_resolution_:
  // the same product res * length * multiplier the search used to form at every step.
  double step_resolution_ = 0.0;
  std::array<double, 256> straight_cost_{};
  std::array<double, 256> diagonal_cost_{};
};

}  // namespace mobot::planning
