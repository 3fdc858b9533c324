#include "core/planning/astar_planner.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "core/numeric/constants.h"
#include "core/planning/grid_search.h"
#include "core/planning/grid_steps.h"

namespace mobot::planning {
namespace {

// Open-list order: smaller f first; among equal f the node nearer the goal (smaller h), which cuts
// the expansions on open ground (1000 instead of most of a 1000 x 1000 grid) without changing the
// cost of the result.
template <typename Node>
bool comes_before(const Node& a, const Node& b) {
  return (a.f < b.f) | ((a.f == b.f) & (a.h < b.h));
}

// A 4-ary min-heap in a flat vector: half the depth of a binary heap, a node's children in one
// cache line. Duplicates are allowed (lazy decrease-key). The A* open list uses it only for the
// nodes pushed into the bucket being popped from; the start escape uses it alone.
// (gnu::always_inline: GCC otherwise leaves these, and the open list's push and pop, as calls in
// the search loop: 5 % more instructions on the maze benchmark.)
constexpr std::size_t kArity = 4;  // heap_pop's tournament is written for four

template <typename Node>
[[gnu::always_inline]] inline void heap_push(std::vector<Node>& heap, const Node& node) {
  std::size_t i = heap.size();
  heap.push_back(node);
  while (i > 0) {
    const std::size_t parent = (i - 1) / kArity;
    if (!comes_before(node, heap[parent])) break;
    heap[i] = heap[parent];
    i = parent;
  }
  heap[i] = node;
}

template <typename Node>
[[gnu::always_inline]] inline Node heap_pop(std::vector<Node>& heap) {
  const Node top = heap.front();
  const Node last = heap.back();
  heap.pop_back();
  const std::size_t size = heap.size();
  if (size == 0) return top;
  std::size_t i = 0;
  for (;;) {
    const std::size_t first = kArity * i + 1;
    if (first >= size) break;
    std::size_t best = first;
    if (first + kArity <= size) {
      // A full node: a fixed tournament, branch-free with integer keys.
      const std::size_t a = comes_before(heap[first + 1], heap[first]) ? first + 1 : first;
      const std::size_t b = comes_before(heap[first + 3], heap[first + 2]) ? first + 3 : first + 2;
      best = comes_before(heap[b], heap[a]) ? b : a;
    } else {
      for (std::size_t child = first + 1; child < size; ++child) {
        best = comes_before(heap[child], heap[best]) ? child : best;
      }
    }
    if (!comes_before(heap[best], last)) break;
    heap[i] = heap[best];
    i = best;
  }
  heap[i] = last;
  return top;
}

// Sorts largest first, so the smallest can be popped from the back. Buckets hold a few nodes on
// the maze benchmarks, where an inlined insertion sort beats std::sort's calls.
template <typename Node>
void sort_largest_first(std::vector<Node>& nodes) {
  const auto larger = [](const Node& a, const Node& b) { return comes_before(b, a); };
  if (nodes.size() > 16) {
    std::sort(nodes.begin(), nodes.end(), larger);
    return;
  }
  for (std::size_t j = 1; j < nodes.size(); ++j) {
    const Node node = nodes[j];
    std::size_t k = j;
    for (; k > 0 && larger(node, nodes[k - 1]); --k) nodes[k] = nodes[k - 1];
    nodes[k] = node;
  }
}

}  // namespace

AStarPlanner::AStarPlanner(const AStarOptions& options) : options_(options) {
  if (!std::isfinite(options.cost_penalty_weight) || options.cost_penalty_weight < 0.0 ||
      !std::isfinite(options.max_escape_distance_m) || options.max_escape_distance_m < 0.0) {
    throw std::invalid_argument("A* options must be finite and non-negative");
  }
  for (std::size_t cost = 0; cost < multiplier_.size(); ++cost) {
    const double clamped = std::min<double>(static_cast<double>(cost), PlanningGrid::kMaxInflated);
    multiplier_[cost] = 1.0 + options.cost_penalty_weight * clamped / PlanningGrid::kMaxInflated;
  }
}

AStarPlanner::HeapNode AStarPlanner::make_node(double f, double h, std::uint32_t index) {
  return {std::bit_cast<std::uint64_t>(f), std::bit_cast<std::uint32_t>(static_cast<float>(h)),
          index};
}

// The open list is a monotone bucket queue that pops in the same exact (f, h) order as a heap:
//
// - Bucket number b(f) = floor((f - f_start) / width) never decreases with f (a subtraction and a
//   multiplication by a positive constant, each rounded, keep the order of their operands), and
//   keys below the bucket being popped from (a child's f can round an ulp below its parent's) are
//   put into that bucket. So every node in a later bucket has a larger f than every node in the
//   current one, and the smallest (f, h) of the current bucket is the smallest of the list.
// - Within the current bucket the order is exact: its nodes are sorted on (f, h) when the list
//   reaches it, and nodes pushed into it meanwhile (about one push in seven on the maze) go to a
//   small heap, `late_`; pop takes the smaller of the two fronts.
// - With a consistent heuristic, a step raises f by at most its cost plus its length (the octile
//   distance is 1-Lipschitz), so no open key lies more than span = res * sqrt2 * (max multiplier
//   + 1) above a key already popped, all of which are below the current bucket's top: a ring of
//   span / width + 3 buckets (the current one, one for where in it the popped key lay, one for
//   rounding) never wraps onto the current bucket.
//
// Versus the former 4-ary heap over the whole list, most pushes are appends and most pops take the
// back of a short sorted run, which removes most of the heap's unpredictable branches.
// Bucket width: 1/64 of a cell, so a bucket holds a few nodes (16 to 128 measured within noise of
// each other on the maze benchmarks), but never more than kMaxBuckets buckets, which bounds the
// ring when a large cost weight widens the span (the buckets then just get wider).
constexpr double kBucketsPerCell = 64.0;
constexpr double kMaxBuckets = 4096.0;

void AStarPlanner::OpenList::reset(double f_start, double span, double resolution) {
  const double width = std::max(resolution / kBucketsPerCell, span / kMaxBuckets);
  const auto needed = static_cast<std::size_t>(std::ceil(span / width)) + 3;
  const std::size_t count = std::bit_ceil(std::max<std::size_t>(needed, 64));  // whole bit words
  if (buckets_.size() != count) {
    buckets_.resize(count);
    occupied_.assign(count / 64, 0);
  }
  if (size_ != 0) {  // the last search stopped at its goal with nodes left
    for (auto& bucket : buckets_) bucket.clear();
    late_.clear();
    std::fill(occupied_.begin(), occupied_.end(), 0);
  }
  mask_ = count - 1;
  current_ = 0;
  f_start_ = f_start;
  inverse_width_ = 1.0 / width;
  size_ = 0;
}

[[gnu::always_inline]] inline void AStarPlanner::OpenList::push(double f, double h,
                                                                std::uint32_t index) {
  const auto bucket =
      std::max(static_cast<std::int64_t>((f - f_start_) * inverse_width_), current_);
  if (bucket == current_) {
    heap_push(late_, make_node(f, h, index));
  } else {
    const auto slot = static_cast<std::size_t>(bucket) & mask_;
    buckets_[slot].push_back(make_node(f, h, index));
    occupied_[slot / 64] |= std::uint64_t{1} << (slot % 64);
  }
  ++size_;
}

[[gnu::always_inline]] inline AStarPlanner::HeapNode AStarPlanner::OpenList::pop() {
  auto slot = static_cast<std::size_t>(current_) & mask_;
  std::vector<HeapNode>* run = &buckets_[slot];
  if (run->empty() && late_.empty()) {
    // On to the next non-empty bucket along the ring (there is one: size_ > 0).
    std::size_t word = slot / 64;
    std::uint64_t bits = occupied_[word] & (~std::uint64_t{0} << (slot % 64));
    while (bits == 0) {
      word = (word + 1) & (mask_ / 64);
      bits = occupied_[word];
    }
    const std::size_t next = word * 64 + static_cast<std::size_t>(std::countr_zero(bits));
    current_ += static_cast<std::int64_t>((next - slot) & mask_);
    slot = next;
    occupied_[slot / 64] &= ~(std::uint64_t{1} << (slot % 64));  // pushes now go to late_
    run = &buckets_[slot];
    sort_largest_first(*run);
  }
  --size_;
  if (late_.empty() || (!run->empty() && comes_before(run->back(), late_.front()))) {
    const HeapNode node = run->back();
    run->pop_back();
    return node;
  }
  return heap_pop(late_);
}

void AStarPlanner::begin_search(std::size_t cell_count, double resolution) {
  ++search_number_;
  if (stamp_.size() != cell_count || search_number_ > kMaxSearchNumber) {
    g_.resize(cell_count);  // read only where the stamp is current: no reset needed
    stamp_.assign(cell_count, 0);
    search_number_ = 1;
  }
  if (resolution != step_resolution_) {
    for (std::size_t cost = 0; cost < multiplier_.size(); ++cost) {
      straight_cost_[cost] = resolution * 1.0 * multiplier_[cost];
      diagonal_cost_[cost] = resolution * std::numbers::sqrt2 * multiplier_[cost];
    }
    step_resolution_ = resolution;
  }
}

bool AStarPlanner::search(const PlanningGrid& grid, mapping::CellIndex start,
                          mapping::CellIndex goal, PlanResult& result) {
  const int width = grid.width();
  const int height = grid.height();
  const double res = grid.resolution_m();
  const std::uint8_t* costs = grid.costs().data();
  begin_search(grid.costs().size(), res);
  // Locals, not members, in the loop: the compiler must reload members after any store it cannot
  // prove unrelated (the open list's vectors).
  Stamp* const stamp = stamp_.data();
  double* const gs = g_.data();
  const double* const straight_cost = straight_cost_.data();
  const double* const diagonal_cost = diagonal_cost_.data();
  // A stamp shifted right by kStepBits: the search number and the closed bit.
  const unsigned open_key = search_number_ << 1;
  const unsigned closed_key = open_key | 1U;
  const auto open_stamp = [open_key](unsigned step) {
    return static_cast<Stamp>((open_key << kStepBits) | step);
  };

  const auto start_index = static_cast<std::uint32_t>(grid.index_of(start));
  const auto goal_index = static_cast<std::uint32_t>(grid.index_of(goal));
  stamp[start_index] = open_stamp(0);
  gs[start_index] = 0.0;
  const double h0 = res * octile_cells(start, goal);
  const double max_multiplier = *std::max_element(multiplier_.begin(), multiplier_.end());
  // The largest rise of f in one step (see OpenList), with a margin for rounding.
  const double span = res * std::numbers::sqrt2 * (max_multiplier + 1.0) * (1.0 + 1e-6);
  open_.reset(h0, span, res);
  open_.push(h0, h0, start_index);

  // Relaxes step kGridSteps[step] from the cell being expanded, at g, to cell (nx, ny) at flat
  // index `next`. The closed test comes first: it is the most frequent way out (half the calls on
  // the maze) and needs no arithmetic. (always_inline: GCC otherwise calls it from its eight sites,
  // 30 % more instructions on the maze benchmark.)
  const auto relax = [&](double g, unsigned step, int nx, int ny, std::uint32_t next,
                         const double* step_cost) __attribute__((always_inline)) {
    const unsigned key = stamp[next] >> kStepBits;
    if (key == closed_key) return;
    const double tentative = g + step_cost[costs[next]];
    if (key == open_key && tentative >= gs[next]) return;
    stamp[next] = open_stamp(step);
    gs[next] = tentative;
    const double h = res * octile_cells({nx, ny}, goal);
    open_.push(tentative + h, h, next);
  };
  const auto free_at = [costs](std::uint32_t index) {
    return PlanningGrid::is_traversable_cost(costs[index]);
  };
  const auto w = static_cast<std::uint32_t>(width);

  while (!open_.empty()) {
    const std::uint32_t i = open_.pop().index;
    if ((stamp[i] >> kStepBits) == closed_key) continue;  // a stale duplicate (lazy decrease-key)
    stamp[i] |= 1U << kStepBits;
    ++result.expanded_cells;
    if (i == goal_index) break;

    // 32-bit division: one instruction yields both coordinates.
    const auto y = static_cast<int>(i / w);
    const auto x = static_cast<int>(i - static_cast<std::uint32_t>(y) * w);
    const double g = gs[i];
    if (x > 0 && y > 0 && x + 1 < width && y + 1 < height) {
      // Interior cell: no bounds checks, and the side cells a diagonal needs (no corner cutting)
      // are the orthogonal neighbours already looked at. Steps numbered as in kGridSteps.
      const bool east = free_at(i + 1);
      const bool west = free_at(i - 1);
      const bool north = free_at(i + w);
      const bool south = free_at(i - w);
      if (east) relax(g, 0, x + 1, y, i + 1, straight_cost);
      if (west) relax(g, 1, x - 1, y, i - 1, straight_cost);
      if (north) relax(g, 2, x, y + 1, i + w, straight_cost);
      if (south) relax(g, 3, x, y - 1, i - w, straight_cost);
      if (north && east && free_at(i + w + 1)) relax(g, 4, x + 1, y + 1, i + w + 1, diagonal_cost);
      if (south && east && free_at(i - w + 1)) relax(g, 5, x + 1, y - 1, i - w + 1, diagonal_cost);
      if (north && west && free_at(i + w - 1)) relax(g, 6, x - 1, y + 1, i + w - 1, diagonal_cost);
      if (south && west && free_at(i - w - 1)) relax(g, 7, x - 1, y - 1, i - w - 1, diagonal_cost);
      continue;
    }
    for (unsigned k = 0; k < kGridSteps.size(); ++k) {
      const GridStep& step = kGridSteps[k];
      const int nx = x + step.dx;
      const int ny = y + step.dy;
      if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
      const auto next = static_cast<std::uint32_t>(ny * width + nx);
      if (!free_at(next)) continue;
      const bool diagonal = step.dx != 0 && step.dy != 0;
      if (diagonal && (!free_at(static_cast<std::uint32_t>(y * width + nx)) ||
                       !free_at(static_cast<std::uint32_t>(ny * width + x)))) {
        continue;
      }
      relax(g, k, nx, ny, next, diagonal ? diagonal_cost : straight_cost);
    }
  }
  if ((stamp[goal_index] >> kStepBits) != closed_key) return false;

  result.cost = gs[goal_index];
  // Back from the goal, each cell to the one whose expansion last lowered its g.
  std::vector<mapping::CellIndex> reversed{goal};
  for (std::uint32_t c = goal_index; c != start_index;) {
    const GridStep& step = kGridSteps[stamp[c] & ((1U << kStepBits) - 1)];
    const mapping::CellIndex from{reversed.back().x - step.dx, reversed.back().y - step.dy};
    reversed.push_back(from);
    c = static_cast<std::uint32_t>(grid.index_of(from));
  }
  result.cells.insert(result.cells.end(), reversed.rbegin(), reversed.rend());
  return true;
}

PlanResult AStarPlanner::plan(const PlanningGrid& grid, const geometry::Pose2D& start,
                              const geometry::Pose2D& goal) {
  return plan_on_grid(grid, start, goal, options_.max_escape_distance_m,
                      [&](mapping::CellIndex from, mapping::CellIndex to, PlanResult& result) {
                        return search(grid, from, to, result);
                      });
}

}  // namespace mobot::planning
