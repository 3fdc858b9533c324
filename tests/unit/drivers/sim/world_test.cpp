#include "drivers/sim/world.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "drivers/sim/world_slice.h"
#include "tests/unit/drivers/sim/sim_test_support.h"

namespace mobot::sim {
namespace {

using testing::builtin_worlds_dir;
using ::testing::HasSubstr;
using testing::TempDir;

constexpr std::uint8_t kFreePixel = 254;
constexpr std::uint8_t kWallPixel = 0;

World load_builtin(const std::string& name) {
  return load_world(resolve_world(builtin_worlds_dir(), name));
}

std::uint8_t cell_at_point(const World& world, double x_m, double y_m) {
  const auto cell = world.floor.cell_at({x_m, y_m});
  EXPECT_TRUE(cell.has_value()) << x_m << ", " << y_m;
  return cell ? world.floor.at(*cell) : mapping::OccupancyGrid::kUnknown;
}

// No ray can escape a map whose border cells are all walls.
void expect_closed_border(const mapping::OccupancyGrid& grid) {
  for (int x = 0; x < grid.width(); ++x) {
    ASSERT_TRUE(grid.is_occupied({x, 0}));
    ASSERT_TRUE(grid.is_occupied({x, grid.height() - 1}));
  }
  for (int y = 0; y < grid.height(); ++y) {
    ASSERT_TRUE(grid.is_occupied({0, y}));
    ASSERT_TRUE(grid.is_occupied({grid.width() - 1, y}));
  }
}

// Every cell within `radius_m` of the point is free.
void expect_clearance(const World& world, double x_m, double y_m, double radius_m) {
  const double step_m = world.floor.resolution_m() / 2.0;
  for (double dx = -radius_m; dx <= radius_m; dx += step_m) {
    for (double dy = -radius_m; dy <= radius_m; dy += step_m) {
      if (std::hypot(dx, dy) > radius_m) continue;
      ASSERT_EQ(cell_at_point(world, x_m + dx, y_m + dy), mapping::OccupancyGrid::kFree)
          << "at " << x_m + dx << ", " << y_m + dy;
    }
  }
}

const Box3D* find_box(const World& world, const std::string& name) {
  for (const auto& box : world.boxes) {
    if (box.name == name) return &box;
  }
  return nullptr;
}

// The share of cells with `clearance_m` to every wall and body-height box that a robot of that
// radius can reach from the start: 1 when every room is reachable through its doors.
double reachable_share(const World& world, double clearance_m) {
  mapping::OccupancyGrid obstacles = world.floor;
  for (const auto& box : world.boxes) {
    if (box.min_z_m < 1.2) rasterize_box(box, obstacles);
  }
  cv::Mat free_mask(obstacles.height(), obstacles.width(), CV_8UC1);
  for (int y = 0; y < obstacles.height(); ++y) {
    for (int x = 0; x < obstacles.width(); ++x) {
      free_mask.at<std::uint8_t>(y, x) = obstacles.is_occupied({x, y}) ? 0 : 255;
    }
  }
  cv::Mat distance_cells;
  cv::distanceTransform(free_mask, distance_cells, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  const auto roomy = [&](mapping::CellIndex c) {
    return obstacles.contains(c) &&
           distance_cells.at<float>(c.y, c.x) * obstacles.resolution_m() >= clearance_m;
  };
  int roomy_cells = 0;
  for (int y = 0; y < obstacles.height(); ++y) {
    for (int x = 0; x < obstacles.width(); ++x) roomy_cells += roomy({x, y}) ? 1 : 0;
  }
  const mapping::CellIndex start = *obstacles.cell_at({world.start.x, world.start.y});
  EXPECT_TRUE(roomy(start));
  std::vector<bool> seen(obstacles.cells().size(), false);
  const auto index = [&](mapping::CellIndex c) {
    return static_cast<std::size_t>(c.y) * static_cast<std::size_t>(obstacles.width()) +
           static_cast<std::size_t>(c.x);
  };
  std::deque<mapping::CellIndex> queue{start};
  seen[index(start)] = true;
  int reached = 0;
  while (!queue.empty()) {
    const mapping::CellIndex cell = queue.front();
    queue.pop_front();
    ++reached;
    for (const auto& next : {mapping::CellIndex{cell.x + 1, cell.y},
                             {cell.x - 1, cell.y},
                             {cell.x, cell.y + 1},
                             {cell.x, cell.y - 1}}) {
      if (roomy(next) && !seen[index(next)]) {
        seen[index(next)] = true;
        queue.push_back(next);
      }
    }
  }
  return static_cast<double>(reached) / roomy_cells;
}

TEST(World, EveryRoomOfTheBuiltInsIsReachable) {
  EXPECT_DOUBLE_EQ(reachable_share(load_builtin("office"), 0.4), 1.0);
  EXPECT_DOUBLE_EQ(reachable_share(load_builtin("g2_lobby"), 0.4), 1.0);
  // The test can fail: a wall with no door cuts the floor in two.
  World closed = testing::empty_world(100, 40, 0.1);
  testing::outer_walls(closed.floor);
  testing::fill_cells(closed.floor, 50, 0, 51, 39);
  closed.start = {2.0, 2.0, 0.0};
  EXPECT_NEAR(reachable_share(closed, 0.4), 0.5, 0.02);
}

TEST(World, LoadsTheOffice) {
  const World world = load_builtin("office");
  EXPECT_EQ(world.name, "office");
  EXPECT_FALSE(world.description.empty());
  EXPECT_EQ(world.floor.width(), 400);
  EXPECT_EQ(world.floor.height(), 300);
  EXPECT_DOUBLE_EQ(world.floor.resolution_m(), 0.05);
  EXPECT_GE(world.landmarks.size(), 4U);
  expect_closed_border(world.floor);
  // The robot starts in the corridor with room around its 0.6 m body.
  expect_clearance(world, world.start.x, world.start.y, 0.3 + 0.6);
  const Box3D* table = find_box(world, "table_1");
  ASSERT_NE(table, nullptr);
  EXPECT_GT(table->min_z_m, 0.4);  // above the laser
  EXPECT_LT(table->min_z_m, 1.2);  // below the top of the robot
}

TEST(World, LoadsTheG2LobbyOfP2) {
  const World world = load_builtin("g2_lobby");
  EXPECT_EQ(world.name, "g2_lobby");
  EXPECT_EQ(world.start, (geometry::Pose2D{0.0, 0.0, std::numbers::pi / 2}));
  EXPECT_EQ(world.floor.width(), 240);
  EXPECT_EQ(world.floor.height(), 240);
  EXPECT_EQ(world.floor.origin(), (geometry::Pose2D{-6.0, -2.0, 0.0}));
  expect_closed_border(world.floor);
  // The wall at y 3.0..3.3 with gate A (x = 0), gate B (x = -2.2) and corridor C (x = 4) open in
  // the floor plan, so a 2D planner sees all three.
  EXPECT_TRUE(world.floor.is_occupied(*world.floor.cell_at({-1.1, 3.15})));
  EXPECT_TRUE(world.floor.is_occupied(*world.floor.cell_at({1.5, 3.15})));
  EXPECT_EQ(cell_at_point(world, 0.0, 3.15), mapping::OccupancyGrid::kFree);
  EXPECT_EQ(cell_at_point(world, -2.2, 3.15), mapping::OccupancyGrid::kFree);
  EXPECT_EQ(cell_at_point(world, 4.0, 3.15), mapping::OccupancyGrid::kFree);
  expect_clearance(world, 0.0, 0.0, 0.9);
  expect_clearance(world, 0.0, 6.8, 0.9);
  const Box3D* beam_a = find_box(world, "gate_a_beam");
  const Box3D* beam_b = find_box(world, "gate_b_beam");
  ASSERT_NE(beam_a, nullptr);
  ASSERT_NE(beam_b, nullptr);
  EXPECT_GT(beam_a->min_z_m, 0.4);
  EXPECT_LT(beam_a->min_z_m, 1.2);
  EXPECT_GT(beam_b->min_z_m, 1.6);
  EXPECT_LT(beam_a->min_x_m, 0.0);
  EXPECT_GT(beam_a->max_x_m, 0.0);
}

TEST(World, ListsTheBuiltInsSortedByName) {
  const auto worlds = list_worlds(builtin_worlds_dir());
  ASSERT_EQ(worlds.size(), 3U);
  EXPECT_EQ(worlds[0].name, "g2_lobby");
  EXPECT_EQ(worlds[1].name, "office");
  EXPECT_EQ(worlds[2].name, "yard");
  EXPECT_FALSE(worlds[0].description.empty());
  EXPECT_TRUE(list_worlds(builtin_worlds_dir() / "no_such_dir").empty());
}

TEST(World, ResolvesNamesAndPaths) {
  const auto office = resolve_world(builtin_worlds_dir(), "office");
  EXPECT_EQ(office, builtin_worlds_dir() / "office" / "world.yaml");
  const std::string path = (builtin_worlds_dir() / "g2_lobby" / "world.yaml").string();
  EXPECT_EQ(resolve_world("/nonexistent", path), path);
}

TEST(World, UnknownWorldNamesTheBuiltIns) {
  try {
    resolve_world(builtin_worlds_dir(), "atlantis");
    FAIL() << "expected WorldError";
  } catch (const WorldError& error) {
    EXPECT_THAT(error.what(), HasSubstr("unknown world 'atlantis'"));
    EXPECT_THAT(error.what(), HasSubstr("office"));
    EXPECT_THAT(error.what(), HasSubstr("g2_lobby"));
  }
  EXPECT_THROW(resolve_world(builtin_worlds_dir(), "/tmp/no/such/world.yaml"), WorldError);
  EXPECT_THROW(resolve_world(builtin_worlds_dir(), ".."), WorldError);
  EXPECT_THROW(resolve_world(builtin_worlds_dir(), ""), WorldError);
}

// A minimal valid world around a 3 x 2 image; `extra` is appended to the YAML.
std::filesystem::path write_small_world(const TempDir& dir, const std::string& extra = "") {
  // Top row: wall, free, free; bottom row: free, free, wall.
  dir.write_pgm("floor.pgm", 3, 2,
                {kWallPixel, kFreePixel, kFreePixel, kFreePixel, kFreePixel, kWallPixel});
  return dir.write("world.yaml",
                   "name: small\nimage: floor.pgm\nresolution: 0.5\norigin: [1.0, 2.0, 0]\n"
                   "start: [1.75, 2.25, 0]\n" +
                       extra);
}

TEST(World, ImageRowZeroIsTheTopOfTheMap) {
  const TempDir dir;
  const World world = load_world(write_small_world(dir));
  ASSERT_EQ(world.floor.width(), 3);
  ASSERT_EQ(world.floor.height(), 2);
  EXPECT_EQ(world.floor.origin(), (geometry::Pose2D{1.0, 2.0, 0.0}));
  EXPECT_EQ(world.floor.at({0, 1}), mapping::OccupancyGrid::kOccupied);  // top-left pixel
  EXPECT_EQ(world.floor.at({2, 0}), mapping::OccupancyGrid::kOccupied);  // bottom-right pixel
  EXPECT_EQ(world.floor.at({0, 0}), mapping::OccupancyGrid::kFree);
  EXPECT_EQ(world.floor.at({2, 1}), mapping::OccupancyGrid::kFree);
  EXPECT_TRUE(world.boxes.empty());
  EXPECT_EQ(world.start, (geometry::Pose2D{1.75, 2.25, 0.0}));
}

std::vector<std::uint8_t> load_single_row(const TempDir& dir, const std::string& options) {
  dir.write_pgm("row.pgm", 4, 1, {0, 100, 200, 254});
  const auto yaml =
      dir.write("world.yaml", "image: row.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n" + options);
  return load_world(yaml).floor.cells();
}

TEST(World, AppliesMapServerTrinaryThresholds) {
  const TempDir dir;
  constexpr std::uint8_t kOcc = mapping::OccupancyGrid::kOccupied;
  constexpr std::uint8_t kFree = mapping::OccupancyGrid::kFree;
  constexpr std::uint8_t kUnk = mapping::OccupancyGrid::kUnknown;
  // p = (255 - v) / 255: 1.0, 0.61, 0.22, 0.004.
  EXPECT_EQ(load_single_row(dir, ""), (std::vector<std::uint8_t>{kOcc, kUnk, kUnk, kFree}));
  EXPECT_EQ(load_single_row(dir, "occupied_thresh: 0.5\nfree_thresh: 0.25\n"),
            (std::vector<std::uint8_t>{kOcc, kOcc, kFree, kFree}));
  // Negated, p = v / 255: 0, 0.39, 0.78, 0.996.
  EXPECT_EQ(load_single_row(dir, "negate: 1\n"),
            (std::vector<std::uint8_t>{kFree, kUnk, kOcc, kOcc}));
  EXPECT_EQ(load_single_row(dir, "negate: true\n"),
            (std::vector<std::uint8_t>{kFree, kUnk, kOcc, kOcc}));
}

TEST(World, ReadsPngBoxesAndLandmarks) {
  const TempDir dir;
  cv::Mat image(2, 2, CV_8UC3, cv::Scalar(254, 254, 254));
  image.at<cv::Vec3b>(0, 1) = cv::Vec3b(0, 0, 0);
  ASSERT_TRUE(cv::imwrite((dir.path() / "floor.png").string(), image));
  const auto yaml =
      dir.write("w.yaml",
                "name: pngworld\ndescription: two by two\nimage: floor.png\nresolution: 1\n"
                "origin: [0, 0, 0]\nstart: [0.5, 0.5, 3.0]\n"
                "boxes:\n  - {name: beam, min: [0.1, 0.2, 0.8], max: [1.5, 0.4, 1.0]}\n"
                "landmarks:\n  - {name: red, x: 1.5, y: 0.25}\n");
  const World world = load_world(yaml);
  EXPECT_EQ(world.name, "pngworld");
  EXPECT_EQ(world.description, "two by two");
  EXPECT_EQ(world.floor.at({1, 1}), mapping::OccupancyGrid::kOccupied);
  EXPECT_EQ(world.floor.at({0, 1}), mapping::OccupancyGrid::kFree);
  ASSERT_EQ(world.boxes.size(), 1U);
  EXPECT_EQ(world.boxes[0].name, "beam");
  EXPECT_DOUBLE_EQ(world.boxes[0].min_x_m, 0.1);
  EXPECT_DOUBLE_EQ(world.boxes[0].max_y_m, 0.4);
  EXPECT_DOUBLE_EQ(world.boxes[0].min_z_m, 0.8);
  EXPECT_DOUBLE_EQ(world.boxes[0].max_z_m, 1.0);
  ASSERT_EQ(world.landmarks.size(), 1U);
  EXPECT_EQ(world.landmarks[0].name, "red");
  EXPECT_DOUBLE_EQ(world.landmarks[0].x_m, 1.5);
}

// Loading must fail with a WorldError whose message holds every one of `fragments`.
void expect_world_error(const std::filesystem::path& yaml,
                        const std::vector<std::string>& fragments) {
  try {
    load_world(yaml);
    ADD_FAILURE() << "expected WorldError for " << yaml;
  } catch (const WorldError& error) {
    for (const auto& fragment : fragments) EXPECT_THAT(error.what(), HasSubstr(fragment));
  }
}

TEST(World, ErrorsNameTheFileAndTheKey) {
  const TempDir dir;
  expect_world_error(dir.path() / "missing.yaml", {"missing.yaml", "does not exist"});
  expect_world_error(dir.write("broken.yaml", "name: [unclosed\n"), {"broken.yaml", "YAML"});
  expect_world_error(dir.write("list.yaml", "- 1\n- 2\n"), {"list.yaml", "mapping"});
  expect_world_error(
      dir.write("noimage.yaml", "image: gone.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n"),
      {"noimage.yaml", "'image'", "gone.pgm"});
  dir.write("garbage.pgm", "this is not an image");
  expect_world_error(
      dir.write("garbage.yaml", "image: garbage.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n"),
      {"garbage.yaml", "'image'", "garbage.pgm"});

  expect_world_error(write_small_world(dir, "ressolution: 0.05\n"),
                     {"world.yaml", "'ressolution'"});
  expect_world_error(write_small_world(dir, "free_thresh: 0.9\n"), {"'free_thresh'"});
  expect_world_error(write_small_world(dir, "occupied_thresh: high\n"), {"'occupied_thresh'"});
  expect_world_error(write_small_world(dir, "negate: maybe\n"), {"'negate'"});
  expect_world_error(write_small_world(dir, "mode: scale\n"), {"'mode'"});
  expect_world_error(
      write_small_world(dir, "boxes:\n  - {name: b, min: [0, 0, 1], max: [1, 1, 1]}\n"),
      {"'boxes[0]'", "min < max"});
  expect_world_error(write_small_world(dir, "boxes:\n  - {name: b, min: [0, 0], max: [1, 1, 1]}\n"),
                     {"'boxes[0].min'"});
  expect_world_error(write_small_world(dir, "boxes:\n  - {min: [0, 0, 0], max: [1, 1, 1]}\n"),
                     {"'boxes[0].name'", "missing"});
  expect_world_error(write_small_world(dir,
                                       "boxes:\n  - {name: b, min: [0, 0, 0], max: [1, 1, 1]}\n"
                                       "  - {name: b, min: [0, 0, 0], max: [1, 1, 1]}\n"),
                     {"'boxes[1].name'", "repeats"});
  expect_world_error(write_small_world(dir, "boxes: 3\n"), {"'boxes'"});
  expect_world_error(write_small_world(dir, "landmarks:\n  - {name: l, x: 1}\n"),
                     {"'landmarks[0].y'"});
  expect_world_error(write_small_world(dir, "landmarks:\n  - {name: l, x: 1, y: 2, z: 3}\n"),
                     {"'landmarks[0].z'", "not a known key"});

  dir.write_pgm("floor.pgm", 1, 1, {kFreePixel});
  const std::string head = "image: floor.pgm\n";
  expect_world_error(dir.write("w.yaml", head + "origin: [0, 0, 0]\n"),
                     {"'resolution'", "missing"});
  expect_world_error(dir.write("w.yaml", head + "resolution: -0.05\norigin: [0, 0, 0]\n"),
                     {"'resolution'", "positive"});
  expect_world_error(dir.write("w.yaml", head + "resolution: fine\norigin: [0, 0, 0]\n"),
                     {"'resolution'", "number"});
  expect_world_error(dir.write("w.yaml", head + "resolution: .nan\norigin: [0, 0, 0]\n"),
                     {"'resolution'", "finite"});
  expect_world_error(dir.write("w.yaml", head + "resolution: 1\n"), {"'origin'", "missing"});
  expect_world_error(dir.write("w.yaml", head + "resolution: 1\norigin: [0, 0]\n"), {"'origin'"});
  expect_world_error(
      dir.write("w.yaml", head + "resolution: 1\norigin: [0, 0, 0]\nstart: [5, 5, 0]\n"),
      {"'start'", "outside"});
}

}  // namespace
}  // namespace mobot::sim

namespace mobot::sim {
namespace {

TEST(SurveyedMap, DrawsFurnitureMarkedOnMapButNotGateBeams) {
  const World office = load_world(resolve_world(MOBOT_DEFAULT_WORLDS_DIR, "office"));
  const mapping::OccupancyGrid surveyed = surveyed_map(office, 1.2);
  const auto table_centre = office.floor.cell_at({15.8, 11.4});
  ASSERT_TRUE(table_centre);
  EXPECT_FALSE(office.floor.is_occupied(*table_centre)) << "the floor plan has no table";
  EXPECT_TRUE(surveyed.is_occupied(*table_centre)) << "the surveyed map has it";
  // A box above the robot is never drawn, even when marked.
  World high = office;
  for (auto& box : high.boxes) box.min_z_m = 1.5, box.max_z_m = 1.6;
  EXPECT_FALSE(surveyed_map(high, 1.2).is_occupied(*table_centre));

  const World lobby = load_world(resolve_world(MOBOT_DEFAULT_WORLDS_DIR, "g2_lobby"));
  EXPECT_EQ(surveyed_map(lobby, 1.2).cells(), lobby.floor.cells())
      << "gate beams are not on the plan: only the 3D sweep finds them";
}

}  // namespace
}  // namespace mobot::sim
