// IPaBD (P2) on synthetic clouds: what passes over the robot, what blocks it, the floor, the order
// of the height filter and the nearest-point step, segmentation, dilation and the layer.
#include "core/perception/ipabd.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/perception/obstacle_layer_3d.h"

namespace mobot::perception {
namespace {

using mapping::OccupancyGrid;

// A wall segment across the robot's way at y = distance, from x0 to x1, at height z: a point every
// centimetre, as a dense sweep would give.
void add_wall(PointCloud& cloud, double distance_m, double x0_m, double x1_m, double z_m) {
  for (double x = x0_m; x <= x1_m + 1e-9; x += 0.01) {
    cloud.push_back(
        {static_cast<float>(x), static_cast<float>(distance_m), static_cast<float>(z_m), 0.5F});
  }
}

void add_floor(PointCloud& cloud, double max_y_m) {
  for (double y = 0.5; y <= max_y_m; y += 0.1) {
    for (double x = -2.0; x <= 2.0; x += 0.1) {
      cloud.push_back({static_cast<float>(x), static_cast<float>(y), 0.01F, 0.2F});
    }
  }
}

bool occupied_at(const OccupancyGrid& grid, double x_m, double y_m) {
  const auto cell = grid.cell_at({x_m, y_m});
  return cell && grid.at(*cell) == OccupancyGrid::kOccupied;
}

std::uint8_t value_at(const OccupancyGrid& grid, double x_m, double y_m) {
  const auto cell = grid.cell_at({x_m, y_m});
  return cell ? grid.at(*cell) : OccupancyGrid::kUnknown;
}

TEST(Ipabd, AnOverhangAboveTheRobotPasses) {
  PointCloud cloud;
  add_wall(cloud, 3.0, -1.0, 1.0, 1.5);  // a beam at 1.5 m, the robot is 1.2 m tall
  const IpabdResult result = run_ipabd(cloud, {0.0, 0.0});
  EXPECT_EQ(result.points_above, cloud.size());
  EXPECT_TRUE(result.bins.empty());
  EXPECT_FALSE(occupied_at(result.obstacles, 0.0, 3.0));
  EXPECT_FALSE(occupied_at(result.dilated, 0.0, 3.0));
}

TEST(Ipabd, AnOverhangBelowTheRobotHeightBlocks) {
  PointCloud cloud;
  add_wall(cloud, 3.1, -1.0, 1.0, 0.9);  // gate A's beam: under 1.2 m
  const IpabdResult result = run_ipabd(cloud, {0.0, 0.0});
  EXPECT_GT(result.bins.size(), 10U);
  for (double x = -0.9; x <= 0.9; x += 0.1) {
    EXPECT_TRUE(occupied_at(result.obstacles, x, 3.1)) << x;
  }
  // The beam's cell is [3.0, 3.2); a 0.3 m dilation is one and a half 0.2 m cells: one more
  // cell toward the robot, not two.
  EXPECT_TRUE(occupied_at(result.dilated, 0.0, 2.9));
  EXPECT_FALSE(occupied_at(result.dilated, 0.0, 2.7));
  EXPECT_FALSE(occupied_at(result.obstacles, 0.0, 2.9));
}

TEST(Ipabd, TheFloorIsRemovedAndMarksFreeSpace) {
  PointCloud cloud;
  add_floor(cloud, 4.0);
  const IpabdResult result = run_ipabd(cloud, {0.0, 0.0});
  EXPECT_EQ(result.points_floor, cloud.size());
  EXPECT_TRUE(result.bins.empty());
  EXPECT_EQ(value_at(result.obstacles, 0.0, 3.0), OccupancyGrid::kFree);
  EXPECT_EQ(value_at(result.obstacles, 0.0, -3.0), OccupancyGrid::kUnknown) << "never seen";
  // A drop below the floor is not floor: it blocks.
  cloud.push_back({0.0F, 2.0F, -0.3F, 0.2F});
  EXPECT_TRUE(occupied_at(run_ipabd(cloud, {0.0, 0.0}).obstacles, 0.0, 2.0));
}

TEST(Ipabd, AHighBeamDoesNotHideALowObstacleBehindIt) {
  PointCloud cloud;
  add_wall(cloud, 2.0, -0.5, 0.5, 1.6);  // a high beam, nearer
  add_wall(cloud, 4.0, -0.5, 0.5, 0.3);  // a low box behind it, on the same bearings
  const IpabdResult result = run_ipabd(cloud, {0.0, 0.0});
  EXPECT_TRUE(occupied_at(result.obstacles, 0.0, 4.0));
  EXPECT_FALSE(occupied_at(result.obstacles, 0.0, 2.0));
  EXPECT_EQ(value_at(result.obstacles, 0.0, 2.0), OccupancyGrid::kFree);
}

TEST(Ipabd, KeepsOnlyTheNearestPointPerBearing) {
  PointCloud cloud;
  add_wall(cloud, 2.0, -0.3, 0.3, 0.5);
  add_wall(cloud, 5.0, -0.5, 0.5, 0.5);  // hidden behind the nearer wall
  const IpabdResult result = run_ipabd(cloud, {0.0, 0.0});
  EXPECT_TRUE(occupied_at(result.obstacles, 0.0, 2.0));
  EXPECT_FALSE(occupied_at(result.obstacles, 0.0, 5.0));
  for (const auto& bin : result.bins) EXPECT_LT(bin.range_m, 5.0F);
}

TEST(Ipabd, SegmentsBreakAtRangeJumpsAndCloseGapsWithinASegment) {
  PointCloud cloud;
  // A wall 7 m away sampled every 0.5 deg (6 cm) and a box at 2 m to its left.
  for (double b = 80.0; b <= 100.0; b += 0.5) {
    const double rad = b * std::numbers::pi / 180.0;
    const double range_m = 7.0 / std::sin(rad);
    cloud.push_back({static_cast<float>(range_m * std::cos(rad)),
                     static_cast<float>(range_m * std::sin(rad)), 0.5F, 0.5F});
  }
  add_wall(cloud, 2.0, -2.0, -1.6, 0.5);
  IpabdOptions options;
  options.max_range_m = 8.0;
  const IpabdResult result = run_ipabd(cloud, {0.0, 0.0}, options);
  ASSERT_EQ(result.segments.size(), 2U);
  // The far wall is one unbroken barrier of cells.
  for (double x = -1.1; x <= 1.1; x += 0.05) {
    EXPECT_TRUE(occupied_at(result.obstacles, x, 7.0)) << x;
  }
  options.pdbs_c0_m = 0.0;
  options.pdbs_c1 = 0.0;  // every point its own segment
  EXPECT_GT(run_ipabd(cloud, {0.0, 0.0}, options).segments.size(), 30U);
}

TEST(Ipabd, CellIsAThirdOfTheRobotAndTheGridSitsOnTheLattice) {
  PointCloud cloud;
  add_wall(cloud, 3.0, -1.0, 1.0, 0.5);
  IpabdOptions options;
  options.lattice_origin = geometry::Point2D{-6.0, -2.0};
  const IpabdResult result = run_ipabd(cloud, {0.13, 0.07}, options);
  EXPECT_DOUBLE_EQ(result.obstacles.resolution_m(), 0.2);
  const double kx = (result.obstacles.origin().x + 6.0) / 0.2;
  const double ky = (result.obstacles.origin().y + 2.0) / 0.2;
  EXPECT_NEAR(kx, std::round(kx), 1e-9);
  EXPECT_NEAR(ky, std::round(ky), 1e-9);
  EXPECT_LE(result.obstacles.origin().x, 0.13 - 8.0);
  EXPECT_GE(result.obstacles.origin().x + result.obstacles.width_m(), 0.13 + 8.0);
}

TEST(Ipabd, PointsBeyondTheRangeAreIgnored) {
  PointCloud cloud;
  add_wall(cloud, 9.0, -0.5, 0.5, 0.5);
  const IpabdResult result = run_ipabd(cloud, {0.0, 0.0});
  EXPECT_EQ(result.points_out_of_range, cloud.size());
  EXPECT_TRUE(result.bins.empty());
}

TEST(Ipabd, RejectsBadOptions) {
  const PointCloud cloud;
  IpabdOptions options;
  options.robot_diameter_m = 0.0;
  EXPECT_THROW(run_ipabd(cloud, {0.0, 0.0}, options), std::invalid_argument);
  options = {};
  options.floor_tolerance_m = std::nan("");
  EXPECT_THROW(run_ipabd(cloud, {0.0, 0.0}, options), std::invalid_argument);
  options = {};
  options.bearing_step_rad = -1.0;
  EXPECT_THROW(run_ipabd(cloud, {0.0, 0.0}, options), std::invalid_argument);
}

TEST(ObstacleLayer3D, ASweepOverwritesWhatItSawAndKeepsTheRest) {
  const OccupancyGrid map(200, 100, 0.05, {-6.0, -2.0, 0.0}, OccupancyGrid::kFree);  // 10 x 5 m
  ObstacleLayer3D layer;
  layer.reset(map, 0.2);
  EXPECT_EQ(layer.grid().width(), 50);
  EXPECT_EQ(layer.grid().height(), 25);
  IpabdOptions options;
  options.lattice_origin = layer.lattice_origin();

  PointCloud first;
  add_wall(first, 1.0, -1.0, 1.0, 0.5);
  EXPECT_GT(layer.apply(run_ipabd(first, {0.0, 0.0}, options).obstacles), 0);
  EXPECT_TRUE(occupied_at(layer.grid(), 0.0, 1.0));

  // A sweep from elsewhere that did not look there leaves the obstacle.
  PointCloud elsewhere;
  add_wall(elsewhere, -1.5, -5.0, -4.0, 0.5);
  layer.apply(run_ipabd(elsewhere, {-4.5, -1.0},
                        [&] {
                          IpabdOptions o = options;
                          o.max_range_m = 1.0;
                          return o;
                        }())
                  .obstacles);
  EXPECT_TRUE(occupied_at(layer.grid(), 0.0, 1.0));

  // A sweep that sees floor there now clears it.
  PointCloud later;
  add_floor(later, 2.0);
  layer.apply(run_ipabd(later, {0.0, 0.0}, options).obstacles);
  EXPECT_EQ(value_at(layer.grid(), 0.0, 1.0), OccupancyGrid::kFree);
}

TEST(ObstacleLayer3D, NeedsAMap) {
  ObstacleLayer3D layer;
  EXPECT_THROW(layer.reset(OccupancyGrid(), 0.2), std::invalid_argument);
  EXPECT_EQ(layer.apply(OccupancyGrid(4, 4, 0.2, {}, OccupancyGrid::kOccupied)), 0);
}

}  // namespace
}  // namespace mobot::perception
