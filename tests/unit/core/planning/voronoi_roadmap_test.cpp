#include "core/planning/voronoi_roadmap.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/mapping/occupancy_grid.h"
#include "core/planning/planning_grid_builder.h"
#include "tests/unit/core/planning/planning_test_maps.h"

namespace mobot::planning {
namespace {

using mapping::CellIndex;
using mapping::OccupancyGrid;

using test_maps::build;
using test_maps::fill;
using test_maps::free_map;
using test_maps::kRes;
using test_maps::outline;

std::vector<CellIndex> roadmap_cells(const VoronoiRoadmap& roadmap) {
  std::vector<CellIndex> cells;
  for (int y = 0; y < roadmap.height(); ++y) {
    for (int x = 0; x < roadmap.width(); ++x) {
      if (roadmap.on_roadmap({x, y})) cells.push_back({x, y});
    }
  }
  return cells;
}

// The roadmap cells 8-connected to `seed`.
std::vector<CellIndex> component_of(const VoronoiRoadmap& roadmap, CellIndex seed) {
  std::vector<std::uint8_t> seen(roadmap.mask().size(), 0);
  const auto index = [&](CellIndex c) {
    return static_cast<std::size_t>(c.y) * static_cast<std::size_t>(roadmap.width()) +
           static_cast<std::size_t>(c.x);
  };
  std::vector<CellIndex> component;
  std::vector<CellIndex> stack{seed};
  seen[index(seed)] = 1;
  while (!stack.empty()) {
    const CellIndex c = stack.back();
    stack.pop_back();
    component.push_back(c);
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const CellIndex n{c.x + dx, c.y + dy};
        if (!roadmap.on_roadmap(n) || seen[index(n)] != 0) continue;
        seen[index(n)] = 1;
        stack.push_back(n);
      }
    }
  }
  return component;
}

TEST(VoronoiRoadmap, StraightCorridorIsItsCentreLineOneCellWide) {
  // Walls in rows 0 and 21: free space spans [1, 21] cells, the centre line is y = 11.
  OccupancyGrid map = free_map(120, 22);
  fill(map, 0, 0, 119, 0, OccupancyGrid::kOccupied);
  fill(map, 0, 21, 119, 21, OccupancyGrid::kOccupied);
  const PlanningGrid grid = build(map);
  const VoronoiRoadmap roadmap(grid);
  for (int x = 0; x < 120; ++x) {
    int in_column = 0;
    for (int y = 0; y < 22; ++y) {
      if (!roadmap.on_roadmap({x, y})) continue;
      ++in_column;
      EXPECT_LE(std::abs(y + 0.5 - 11.0), 1.0) << x << "," << y;
    }
    EXPECT_EQ(in_column, 1) << "column " << x;
  }
  EXPECT_EQ(roadmap.size(), 120U);
  EXPECT_NEAR(roadmap.clearance_m({60, 10}), 0.5, 1e-12);
  EXPECT_EQ(roadmap.site_of({60, 10}), (CellIndex{60, 0}));
}

// A corridor 24 cells wide at slope 1/2 (about 27 degrees), walls everything else: rasterised
// sloped walls, whose protruding cells are two apart.
struct SlopedCorridor {
  PlanningGrid grid;
  // Perpendicular distance in cells from a cell's centre to the corridor's centre line.
  double off_centre_cells(CellIndex c) const {
    return std::abs((c.y + 0.5) - 0.5 * (c.x + 0.5) - 20.0) / std::sqrt(1.25);
  }
};

SlopedCorridor sloped_corridor() {
  OccupancyGrid map(200, 140, kRes, {}, OccupancyGrid::kOccupied);
  SlopedCorridor corridor;
  for (int y = 0; y < 140; ++y) {
    for (int x = 0; x < 200; ++x) {
      if (corridor.off_centre_cells({x, y}) < 12.0) map.set({x, y}, OccupancyGrid::kFree);
    }
  }
  corridor.grid = build(map);
  return corridor;
}

TEST(VoronoiRoadmap, SlopedCorridorIsItsCentreLineWithoutHairs) {
  const SlopedCorridor corridor = sloped_corridor();
  const VoronoiRoadmap roadmap(corridor.grid);
  const std::vector<CellIndex> cells = roadmap_cells(roadmap);
  ASSERT_FALSE(cells.empty());
  for (const CellIndex c : cells) {
    // Where the grid's border cuts the corridor off (no wall there) the diagram bends a little.
    if (c.x < 3 || c.x >= 197) continue;
    EXPECT_LE(corridor.off_centre_cells(c), 1.0) << c.x << "," << c.y;
  }
  // Along the whole length: every column has a roadmap cell.
  for (int x = 0; x < 200; ++x) {
    int in_column = 0;
    for (int y = 0; y < 140; ++y) in_column += roadmap.on_roadmap({x, y}) ? 1 : 0;
    EXPECT_GE(in_column, 1) << "column " << x;
  }

  // Lau's criterion alone marks the bisectors between wall cells two apart: hairs across the
  // corridor. This is what min_passage_width_m is for.
  VoronoiRoadmapOptions plain;
  plain.min_passage_width_m = 0.0;
  const VoronoiRoadmap hairy(corridor.grid, plain);
  int off_centre = 0;
  for (const CellIndex c : roadmap_cells(hairy)) off_centre += corridor.off_centre_cells(c) > 1.5;
  EXPECT_GT(off_centre, 20);
}

// Two 4.9 x 4.9 m rooms side by side, the dividing wall in columns 99 and 100 with a door of
// door_cells cells centred on y = 50.
OccupancyGrid two_rooms(int door_cells) {
  OccupancyGrid map = free_map(200, 100);
  outline(map);
  fill(map, 99, 0, 100, 99, OccupancyGrid::kOccupied);
  fill(map, 99, 50 - door_cells / 2, 100, 50 + door_cells / 2 - 1, OccupancyGrid::kFree);
  return map;
}

TEST(VoronoiRoadmap, PassesThroughTheMiddleOfADoorAndConnectsBothRooms) {
  const PlanningGrid grid = build(two_rooms(20));  // a 1.0 m door
  const VoronoiRoadmap roadmap(grid);
  std::vector<CellIndex> in_door;
  for (int x = 99; x <= 100; ++x) {
    for (int y = 0; y < 100; ++y) {
      if (roadmap.on_roadmap({x, y})) in_door.push_back({x, y});
    }
  }
  ASSERT_FALSE(in_door.empty());
  for (const CellIndex c : in_door) EXPECT_LE(std::abs(c.y + 0.5 - 50.0), 1.0) << c.y;

  // The door's roadmap runs on into both rooms, deep enough to reach their own diagrams.
  const std::vector<CellIndex> component = component_of(roadmap, in_door.front());
  bool left = false;
  bool right = false;
  for (const CellIndex c : component) {
    left = left || c.x < 40;
    right = right || c.x > 160;
  }
  EXPECT_TRUE(left);
  EXPECT_TRUE(right);
}

TEST(VoronoiRoadmap, PassageNarrowerThanTheRobotHasNoRoadmap) {
  // A 0.5 m door: the 0.6 m robot does not fit, so no cell in it is traversable.
  const PlanningGrid grid = build(two_rooms(10));
  const VoronoiRoadmap roadmap(grid);
  for (int x = 93; x <= 106; ++x) {
    for (int y = 0; y < 100; ++y) EXPECT_FALSE(roadmap.on_roadmap({x, y})) << x << "," << y;
  }
  // The rooms keep theirs.
  EXPECT_GT(roadmap.size(), 100U);
}

TEST(VoronoiRoadmap, SitesAreTheExactNearestObstacles) {
  // Brute force over every cell of random grids, sparse to dense, lethal and unknown obstacles,
  // shapes that are wide, tall and one cell thin.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int checked = 0;
  for (const auto& [width, height] : {std::pair{23, 17}, std::pair{1, 30}, std::pair{30, 1},
                                      std::pair{40, 9}, std::pair{9, 40}}) {
    for (const double density : {0.002, 0.02, 0.2, 0.6}) {
      PlanningGrid grid(width, height, kRes, {});
      std::vector<CellIndex> obstacles;
      for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
          const double r = u(rng);
          if (r >= density) continue;
          grid.set_cost({x, y}, r < density / 2 ? PlanningGrid::kLethal : PlanningGrid::kUnknown);
          obstacles.push_back({x, y});
        }
      }
      // Costs that are not obstacles must not become sites.
      for (int i = 0; i < 5; ++i) {
        const CellIndex c{static_cast<int>(u(rng) * width), static_cast<int>(u(rng) * height)};
        if (grid.cost(c) == PlanningGrid::kFree) grid.set_cost(c, PlanningGrid::kInscribed);
      }
      const VoronoiRoadmap roadmap(grid);
      for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
          const auto site = roadmap.site_of({x, y});
          if (obstacles.empty()) {
            EXPECT_FALSE(site.has_value());
            EXPECT_EQ(roadmap.clearance_cells({x, y}), std::numeric_limits<double>::infinity());
            continue;
          }
          int best = std::numeric_limits<int>::max();
          for (const CellIndex o : obstacles) {
            best = std::min(best, (o.x - x) * (o.x - x) + (o.y - y) * (o.y - y));
          }
          ASSERT_TRUE(site.has_value());
          const std::uint8_t cost = grid.cost(*site);
          EXPECT_TRUE(cost == PlanningGrid::kLethal || cost == PlanningGrid::kUnknown);
          const int d2 = (site->x - x) * (site->x - x) + (site->y - y) * (site->y - y);
          ASSERT_EQ(d2, best) << width << "x" << height << " at " << x << "," << y;
          EXPECT_DOUBLE_EQ(roadmap.clearance_m({x, y}), std::sqrt(best) * kRes);
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(checked, 2000);
}

TEST(VoronoiRoadmap, KeepsOnlyTraversableCellsAndIsReproducible) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> coordinate(0, 159);
  std::uniform_int_distribution<int> extent(2, 20);
  std::size_t total = 0;
  for (int trial = 0; trial < 10; ++trial) {
    OccupancyGrid map = free_map(160, 160);
    outline(map);
    for (int k = 0; k < 15; ++k) {
      const int x = coordinate(rng);
      const int y = coordinate(rng);
      fill(map, x, y, std::min(159, x + extent(rng)), std::min(159, y + extent(rng)),
           k % 5 == 0 ? OccupancyGrid::kUnknown : OccupancyGrid::kOccupied);
    }
    const PlanningGrid grid = build(map);
    const VoronoiRoadmap roadmap(grid);
    for (const CellIndex c : roadmap_cells(roadmap)) {
      ASSERT_TRUE(grid.is_traversable(c));
      // The clearance the traversable band promises: more than the inscribed radius.
      ASSERT_GT(roadmap.clearance_m(c), 0.3);
    }
    EXPECT_EQ(VoronoiRoadmap(grid).mask(), roadmap.mask());
    total += roadmap.size();
  }
  EXPECT_GT(total, 1000U);
}

TEST(VoronoiRoadmap, EmptyAndObstacleFreeGridsHaveNoRoadmap) {
  const VoronoiRoadmap none;
  EXPECT_TRUE(none.empty());
  EXPECT_FALSE(none.on_roadmap({0, 0}));
  EXPECT_FALSE(none.site_of({0, 0}).has_value());

  const VoronoiRoadmap empty_grid{PlanningGrid()};
  EXPECT_TRUE(empty_grid.empty());

  const PlanningGrid open(50, 40, kRes, {});
  const VoronoiRoadmap roadmap(open);
  EXPECT_FALSE(roadmap.empty());
  EXPECT_EQ(roadmap.size(), 0U);
  EXPECT_FALSE(roadmap.site_of({10, 10}).has_value());
  EXPECT_FALSE(roadmap.site_of({50, 10}).has_value());  // outside
}

TEST(VoronoiRoadmap, RejectsBadOptions) {
  const PlanningGrid grid(5, 5, kRes, {});
  VoronoiRoadmapOptions options;
  options.min_passage_width_m = -0.1;
  EXPECT_THROW(VoronoiRoadmap(grid, options), std::invalid_argument);
  options.min_passage_width_m = std::nan("");
  EXPECT_THROW(VoronoiRoadmap(grid, options), std::invalid_argument);
}

}  // namespace
}  // namespace mobot::planning
