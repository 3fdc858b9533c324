#include "core/slam/probability_grid.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <gtest/gtest.h>

namespace mobot::slam {
namespace {

TEST(GridLimits, CoversThePointsOnResolutionMultiples) {
  const std::vector<geometry::Point2D> points = {{0.12, -0.33}, {1.01, 0.52}};
  const GridLimits limits = GridLimits::covering(points, 0.05, 0.1);
  EXPECT_NEAR(limits.origin_x_m, 0.0, 1e-12);
  EXPECT_NEAR(limits.origin_y_m, -0.45, 1e-12);
  EXPECT_GE(limits.origin_x_m + limits.width * 0.05, 1.11 - 1e-9);
  EXPECT_GE(limits.origin_y_m + limits.height * 0.05, 0.62 - 1e-9);
  EXPECT_EQ(GridLimits::covering({}, 0.05, 0.1).width, 0);
  EXPECT_THROW(GridLimits::covering(points, 0.0, 0.1), std::invalid_argument);
  EXPECT_THROW(GridLimits::covering(points, 0.05, -1.0), std::invalid_argument);
}

TEST(ProbabilityGrid, SmearIsOneOnThePointAndDecaysWithSigma) {
  GridLimits limits;
  limits.width = 40;
  limits.height = 40;
  ProbabilityGrid grid(limits);
  const geometry::Point2D point{1.025, 1.025};  // the centre of cell (20, 20)
  grid.smear_points(std::vector<geometry::Point2D>{point}, 0.07);
  EXPECT_NEAR(grid.at(20, 20), 1.0, 0.01);
  EXPECT_NEAR(grid.at(22, 20), std::exp(-0.1 * 0.1 / (2 * 0.07 * 0.07)), 0.02);
  EXPECT_FLOAT_EQ(grid.at(30, 20), 0.0F);  // beyond 3 sigma
  EXPECT_FLOAT_EQ(grid.at(-1, 20), 0.0F);  // outside
  // A second, farther point never lowers a cell (max, not sum).
  grid.smear_points(std::vector<geometry::Point2D>{{1.125, 1.025}}, 0.07);
  EXPECT_NEAR(grid.at(20, 20), 1.0, 0.01);
  EXPECT_LE(grid.at(21, 20), 1.0F);
}

// A wall seen at a grazing angle: returns 0.5 m apart on one line. Joined they form an even ridge;
// as separate bumps the field between them would be empty.
TEST(ProbabilityGrid, SparseCollinearReturnsAreJoinedIntoOneRidge) {
  GridLimits limits;
  limits.width = 60;
  limits.height = 40;
  const std::vector<geometry::Point2D> wall = {
      {0.225, 1.025}, {0.725, 1.025}, {1.225, 1.025}, {1.725, 1.025}, {2.225, 1.025}};
  ProbabilityGrid joined(limits);
  joined.smear_polyline(wall, 0.05, 0.25, 1.0, 0.05);
  ProbabilityGrid bumps(limits);
  bumps.smear_polyline(wall, 0.05, 0.25);
  // Cell 19 is midway between the second and third returns; 29 between the third and fourth.
  EXPECT_NEAR(joined.at(19, 20), 1.0, 0.01);
  EXPECT_NEAR(joined.at(29, 20), 1.0, 0.01);
  EXPECT_LT(bumps.at(19, 20), 0.01F);
  // The outer pairs have no outer neighbour to confirm the line: left as points.
  EXPECT_LT(joined.at(9, 20), 0.01F);
}

// A beam passing a door jamb into the room behind: consecutive returns within the gap but not on
// one line stay apart.
TEST(ProbabilityGrid, ReturnsOffTheLineAreNotJoined) {
  GridLimits limits;
  limits.width = 80;
  limits.height = 40;
  const std::vector<geometry::Point2D> jamb = {{0.225, 1.025}, {0.725, 1.025}, {1.225, 1.425},
                                               {1.725, 1.425}, {2.225, 1.425}, {2.725, 1.425}};
  ProbabilityGrid grid(limits);
  grid.smear_polyline(jamb, 0.05, 0.25, 1.0, 0.05);
  EXPECT_LT(grid.at(19, 24), 0.05F) << "the segment across the jamb was drawn";
  // Beyond the jamb the room's wall is one ridge once a pair has a collinear return on each side.
  EXPECT_NEAR(grid.at(39, 28), 1.0, 0.01);
  EXPECT_THROW(grid.smear_polyline(jamb, 0.05, 0.25, -1.0, 0.05), std::invalid_argument);
  EXPECT_THROW(grid.smear_polyline(jamb, 0.05, 0.25, 1.0, -0.05), std::invalid_argument);
}

TEST(ProbabilityGrid, SkipsNonFinitePointsAndRejectsBadSigma) {
  GridLimits limits;
  limits.width = 10;
  limits.height = 10;
  ProbabilityGrid grid(limits);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  grid.smear_points(std::vector<geometry::Point2D>{{nan, 0.2}, {0.2, nan}}, 0.07);
  for (float v : grid.cells()) EXPECT_FLOAT_EQ(v, 0.0F);
  EXPECT_THROW(grid.smear_points(std::vector<geometry::Point2D>{}, 0.0), std::invalid_argument);
  EXPECT_THROW(grid.smear_points(std::vector<geometry::Point2D>{}, nan), std::invalid_argument);
  limits.width = -1;
  EXPECT_THROW(ProbabilityGrid{limits}, std::invalid_argument);
}

TEST(ProbabilityGrid, InterpolationMatchesFiniteDifferences) {
  GridLimits limits;
  limits.width = 60;
  limits.height = 60;
  ProbabilityGrid grid(limits);
  grid.smear_points(std::vector<geometry::Point2D>{{1.5, 1.5}, {1.6, 1.52}, {1.55, 1.7}}, 0.07);
  for (const geometry::Point2D p : {geometry::Point2D{1.53, 1.47}, geometry::Point2D{1.61, 1.6}}) {
    const auto s = grid.interpolate(p.x, p.y);
    const double h = 1e-5;
    const double gx =
        (grid.interpolate(p.x + h, p.y).value - grid.interpolate(p.x - h, p.y).value) / (2 * h);
    const double gy =
        (grid.interpolate(p.x, p.y + h).value - grid.interpolate(p.x, p.y - h).value) / (2 * h);
    EXPECT_NEAR(s.d_dx, gx, 1e-4 * (1.0 + std::abs(gx)));
    EXPECT_NEAR(s.d_dy, gy, 1e-4 * (1.0 + std::abs(gy)));
    EXPECT_GT(s.value, 0.3);
  }
  // At a cell centre the interpolation is the cell.
  EXPECT_NEAR(grid.interpolate(1.525, 1.525).value, grid.at(30, 30), 1e-6);
  EXPECT_DOUBLE_EQ(grid.interpolate(100.0, 1.0).value, 0.0);
  EXPECT_DOUBLE_EQ(grid.interpolate(std::nan(""), 1.0).value, 0.0);
  EXPECT_DOUBLE_EQ(ProbabilityGrid().interpolate(0.0, 0.0).value, 0.0);
}

}  // namespace
}  // namespace mobot::slam
