#include "core/perception/map_line_extractor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

namespace mobot::perception {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRes = 0.05;

using mapping::CellIndex;
using mapping::OccupancyGrid;

// A rectangular ring of wall cells [x0, x1] x [y0, y1], `thickness` cells thick, free inside.
void draw_room(OccupancyGrid& grid, int x0, int y0, int x1, int y1, int thickness) {
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const bool wall =
          x < x0 + thickness || x > x1 - thickness || y < y0 + thickness || y > y1 - thickness;
      grid.set({x, y}, wall ? OccupancyGrid::kOccupied : OccupancyGrid::kFree);
    }
  }
}

int find_line(const std::vector<LineSegment>& lines, double rho, double alpha, double rho_tol,
              double alpha_tol) {
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (std::abs(lines[i].rho_m - rho) < rho_tol &&
        std::abs(geometry::wrap_angle(lines[i].alpha_rad - alpha)) < alpha_tol) {
      return static_cast<int>(i);
    }
  }
  return -1;
}

std::string describe(const std::vector<LineSegment>& lines) {
  std::string out;
  for (const auto& l : lines) {
    out += "(rho " + std::to_string(l.rho_m) + ", alpha " + std::to_string(l.alpha_rad) + ", len " +
           std::to_string(l.length_m()) + ") ";
  }
  return out;
}

TEST(MapLineExtractor, RectangleRoomGivesItsFourInnerFaces) {
  OccupancyGrid grid(120, 80, kRes, {-1.0, -2.0, 0.0});
  draw_room(grid, 10, 10, 109, 69, 2);  // interior cells 12..107 x 12..67, outside unknown
  const auto lines = extract_map_lines(grid);
  ASSERT_EQ(lines.size(), 4U) << describe(lines);
  // Faces at cell edges: x = 12 res - 1 = -0.4, x = 108 res - 1 = 4.4, y = 12 res - 2 = -1.4,
  // y = 68 res - 2 = 1.4.
  const int left = find_line(lines, 0.4, kPi, 1e-6, 1e-6);
  const int right = find_line(lines, 4.4, 0.0, 1e-6, 1e-6);
  const int bottom = find_line(lines, 1.4, -kPi / 2, 1e-6, 1e-6);
  const int top = find_line(lines, 1.4, kPi / 2, 1e-6, 1e-6);
  ASSERT_GE(left, 0) << describe(lines);
  ASSERT_GE(right, 0) << describe(lines);
  ASSERT_GE(bottom, 0) << describe(lines);
  ASSERT_GE(top, 0) << describe(lines);
  // Each face spans (almost) the whole wall: 4.8 m and 2.8 m.
  EXPECT_NEAR(lines[bottom].length_m(), 4.8, 2 * kRes);
  EXPECT_NEAR(lines[left].length_m(), 2.8, 2 * kRes);
  for (const auto& line : lines) {
    EXPECT_TRUE(is_valid(line));
    EXPECT_GT(line.var_rho_m2, 0.0);
    EXPECT_GT(line.var_alpha_rad2, 0.0);
  }
}

TEST(MapLineExtractor, KnownOutsideAddsTheOuterFaces) {
  OccupancyGrid grid(120, 80, kRes, {}, OccupancyGrid::kFree);
  draw_room(grid, 10, 10, 109, 69, 2);
  const auto lines = extract_map_lines(grid);
  ASSERT_EQ(lines.size(), 8U) << describe(lines);
  // Outer faces at x = 10 and 110 cells, inner ones at 12 and 108.
  EXPECT_GE(find_line(lines, 10 * kRes, 0.0, 1e-6, 1e-6), 0) << describe(lines);
  EXPECT_GE(find_line(lines, 110 * kRes, 0.0, 1e-6, 1e-6), 0) << describe(lines);
  EXPECT_GE(find_line(lines, 12 * kRes, 0.0, 1e-6, 1e-6), 0) << describe(lines);
  EXPECT_GE(find_line(lines, 108 * kRes, 0.0, 1e-6, 1e-6), 0) << describe(lines);

  MapLineExtractorOptions all_faces;
  all_faces.require_free_side = false;
  OccupancyGrid unknown_outside(120, 80, kRes, {});
  draw_room(unknown_outside, 10, 10, 109, 69, 2);
  EXPECT_EQ(extract_map_lines(unknown_outside, all_faces).size(), 8U);
}

TEST(MapLineExtractor, ThinWallGivesBothFaces) {
  OccupancyGrid grid(100, 60, kRes, {}, OccupancyGrid::kFree);
  for (int x = 20; x < 80; ++x) grid.set({x, 30}, OccupancyGrid::kOccupied);
  const auto lines = extract_map_lines(grid);
  ASSERT_EQ(lines.size(), 2U) << describe(lines);
  // Faces at y = 30 and 31 cells; the origin lies below both.
  EXPECT_GE(find_line(lines, 30 * kRes, kPi / 2, 1e-6, 1e-6), 0) << describe(lines);
  EXPECT_GE(find_line(lines, 31 * kRes, kPi / 2, 1e-6, 1e-6), 0) << describe(lines);
  // The lower face looks onto free space toward the origin, the upper one away from it.
  EXPECT_EQ(
      lines[static_cast<std::size_t>(find_line(lines, 30 * kRes, kPi / 2, 1e-6, 1e-6))].free_side,
      -1);
  EXPECT_EQ(
      lines[static_cast<std::size_t>(find_line(lines, 31 * kRes, kPi / 2, 1e-6, 1e-6))].free_side,
      1);
}

TEST(MapLineExtractor, EveryFaceKnowsItsFreeSideInTheMapFrame) {
  // A rotated, shifted map: the free side must survive the move into the map frame.
  OccupancyGrid grid(120, 80, kRes, {3.0, -2.0, 0.7});
  draw_room(grid, 10, 10, 109, 69, 2);
  for (int x = 30; x < 90; ++x) grid.set({x, 40}, OccupancyGrid::kOccupied);
  const auto lines = extract_map_lines(grid);
  ASSERT_GE(lines.size(), 6U) << describe(lines);
  for (const auto& line : lines) {
    ASSERT_NE(line.free_side, 0);
    const geometry::Point2D mid{(line.start.x + line.end.x) / 2, (line.start.y + line.end.y) / 2};
    const double nx = std::cos(line.alpha_rad) * line.free_side;
    const double ny = std::sin(line.alpha_rad) * line.free_side;
    const auto free_cell = grid.cell_at({mid.x + 0.08 * nx, mid.y + 0.08 * ny});
    const auto wall_cell = grid.cell_at({mid.x - 0.02 * nx, mid.y - 0.02 * ny});
    ASSERT_TRUE(free_cell && wall_cell);
    EXPECT_EQ(grid.at(*free_cell), OccupancyGrid::kFree) << describe({line});
    EXPECT_EQ(grid.at(*wall_cell), OccupancyGrid::kOccupied) << describe({line});
  }
}

TEST(MapLineExtractor, DiagonalWallIsOneLinePerFace) {
  OccupancyGrid grid(100, 100, kRes, {}, OccupancyGrid::kFree);
  // A 45 deg staircase two cells thick from (20, 20) to (79, 79).
  for (int i = 20; i < 80; ++i) {
    grid.set({i, i}, OccupancyGrid::kOccupied);
    grid.set({i + 1, i}, OccupancyGrid::kOccupied);
  }
  const auto lines = extract_map_lines(grid);
  ASSERT_EQ(lines.size(), 2U) << describe(lines);
  for (const auto& line : lines) {
    // Normal at -45 deg (below-right face) or 135 deg (above-left face).
    const double folded = geometry::wrap_angle(2.0 * (line.alpha_rad + kPi / 4));
    EXPECT_NEAR(folded, 0.0, 0.02) << describe(lines);
    EXPECT_GT(line.length_m(), 2.5);
  }
}

TEST(MapLineExtractor, OriginPoseMovesTheLinesIntoTheMapFrame) {
  const geometry::Pose2D origin{2.0, -1.0, 0.3};
  OccupancyGrid rotated(120, 80, kRes, origin);
  OccupancyGrid plain(120, 80, kRes, {});
  draw_room(rotated, 10, 10, 109, 69, 2);
  draw_room(plain, 10, 10, 109, 69, 2);
  const auto in_map = extract_map_lines(rotated);
  const auto in_grid = extract_map_lines(plain);
  ASSERT_EQ(in_map.size(), in_grid.size());
  for (const auto& line : in_grid) {
    const LineSegment expected = transform_line(origin, line);
    EXPECT_GE(find_line(in_map, expected.rho_m, expected.alpha_rad, 1e-9, 1e-9), 0)
        << describe(in_map);
  }
}

TEST(MapLineExtractor, NothingToSeeGivesNoLines) {
  EXPECT_TRUE(extract_map_lines(OccupancyGrid()).empty());
  EXPECT_TRUE(extract_map_lines(OccupancyGrid(50, 50, kRes, {})).empty());
  EXPECT_TRUE(extract_map_lines(OccupancyGrid(50, 50, kRes, {}, OccupancyGrid::kFree)).empty());
  // Entirely occupied: the outline borders nothing free.
  EXPECT_TRUE(extract_map_lines(OccupancyGrid(50, 50, kRes, {}, OccupancyGrid::kOccupied)).empty());
  // Specks shorter than min_length_m.
  OccupancyGrid specks(50, 50, kRes, {}, OccupancyGrid::kFree);
  specks.set({10, 10}, OccupancyGrid::kOccupied);
  specks.set({30, 30}, OccupancyGrid::kOccupied);
  specks.set({31, 30}, OccupancyGrid::kOccupied);
  EXPECT_TRUE(extract_map_lines(specks).empty());
}

TEST(MapLineExtractor, IsDeterministic) {
  OccupancyGrid grid(120, 80, kRes, {}, OccupancyGrid::kFree);
  draw_room(grid, 10, 10, 109, 69, 3);
  for (int x = 30; x < 60; ++x) grid.set({x, 40}, OccupancyGrid::kOccupied);
  const auto a = extract_map_lines(grid);
  const auto b = extract_map_lines(grid);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].rho_m, b[i].rho_m);
    EXPECT_EQ(a[i].alpha_rad, b[i].alpha_rad);
  }
}

}  // namespace
}  // namespace mobot::perception
