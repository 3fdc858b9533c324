#include "core/slam/map_renderer.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "tests/unit/core/slam/synthetic_room.h"

namespace mobot::slam {
namespace {

TEST(MapRenderer, MarksWallsOccupiedTheSpaceBeforeThemFreeAndBehindThemUnknown) {
  const auto walls = testing::synthetic_room();
  const geometry::Pose2D base{3.0, 2.0, 0.0};
  const ScanPoints scan = scan_to_points(testing::cast_scan(walls, base));
  const std::vector<PosedScan> scans{{base, &scan}};
  const mapping::OccupancyGrid grid = render_occupancy_grid(scans);
  ASSERT_GT(grid.width(), 0);
  auto value_at = [&](double x, double y) { return grid.at(*grid.cell_at({x, y})); };
  // Every return's cell is a wall: the bottom wall, the stub, the pillar alike.
  for (const auto& p : scan.points_in_base) {
    EXPECT_EQ(value_at(p.x + base.x, p.y + base.y), mapping::OccupancyGrid::kOccupied);
  }
  EXPECT_EQ(value_at(4.0, 2.0), mapping::OccupancyGrid::kFree);
  EXPECT_EQ(value_at(3.0, -0.3), mapping::OccupancyGrid::kUnknown);  // outside the room
  EXPECT_EQ(value_at(7.0, 1.0), mapping::OccupancyGrid::kUnknown);   // behind the stub
  EXPECT_DOUBLE_EQ(grid.resolution_m(), 0.05);
}

TEST(MapRenderer, AlignsTheOriginToTheTileSize) {
  const auto walls = testing::synthetic_room();
  const geometry::Pose2D base{3.0, 2.0, 0.0};
  const ScanPoints scan = scan_to_points(testing::cast_scan(walls, base));
  const std::vector<PosedScan> scans{{base, &scan}};
  MapRenderOptions options;
  options.align_m = 3.2;
  const auto grid = render_occupancy_grid(scans, options);
  EXPECT_NEAR(std::remainder(grid.origin().x, 3.2), 0.0, 1e-9);
  EXPECT_NEAR(std::remainder(grid.origin().y, 3.2), 0.0, 1e-9);
  EXPECT_LE(grid.origin().x, -0.5);
}

TEST(MapRenderer, EmptyForNoScansAndRejectsBadOptions) {
  EXPECT_EQ(render_occupancy_grid({}).width(), 0);
  const std::vector<PosedScan> null_scan{{{}, nullptr}};
  EXPECT_EQ(render_occupancy_grid(null_scan).width(), 0);
  MapRenderOptions bad;
  bad.resolution_m = 0.0;
  EXPECT_THROW(render_occupancy_grid({}, bad), std::invalid_argument);
  bad = {};
  bad.align_m = -1.0;
  EXPECT_THROW(render_occupancy_grid({}, bad), std::invalid_argument);
  bad = {};
  bad.occupied_hit_ratio = 0.0;
  EXPECT_THROW(render_occupancy_grid({}, bad), std::invalid_argument);
  bad = {};
  bad.min_visits = 0;
  EXPECT_THROW(render_occupancy_grid({}, bad), std::invalid_argument);
  bad = {};
  bad.max_range_m = std::nan("");
  EXPECT_THROW(render_occupancy_grid({}, bad), std::invalid_argument);
}

}  // namespace
}  // namespace mobot::slam
