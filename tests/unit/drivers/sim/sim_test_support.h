#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/mapping/occupancy_grid.h"
#include "drivers/sim/world.h"

namespace mobot::sim::testing {

inline std::filesystem::path builtin_worlds_dir() {
  return std::filesystem::path(MOBOT_SOURCE_ROOT) / "drivers" / "sim" / "worlds";
}

// A scratch directory named after the running test, removed again at the end.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("mobot_sim_" + std::string(info->test_suite_name()) + "_" + info->name());
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }

  std::filesystem::path write(const std::string& name, const std::string& text) const {
    const auto file = path_ / name;
    std::ofstream(file, std::ios::binary) << text;
    return file;
  }

  // A binary PGM; pixels are given top row first, as the file stores them.
  std::filesystem::path write_pgm(const std::string& name, int width, int height,
                                  const std::vector<std::uint8_t>& pixels) const {
    std::string text = "P5\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n";
    text.append(pixels.begin(), pixels.end());
    return write(name, text);
  }

 private:
  std::filesystem::path path_;
};

// A world with an empty (free) floor of the given size and walls drawn by the caller.
inline World empty_world(int width_cells, int height_cells, double resolution_m,
                         geometry::Pose2D origin = {}) {
  World world;
  world.name = "test";
  world.floor = mapping::OccupancyGrid(width_cells, height_cells, resolution_m, origin,
                                       mapping::OccupancyGrid::kFree);
  return world;
}

inline void fill_cells(mapping::OccupancyGrid& grid, int min_x, int min_y, int max_x, int max_y,
                       std::uint8_t value = mapping::OccupancyGrid::kOccupied) {
  for (int y = min_y; y <= max_y; ++y) {
    for (int x = min_x; x <= max_x; ++x) grid.set({x, y}, value);
  }
}

// Closes the grid's border with one-cell walls.
inline void outer_walls(mapping::OccupancyGrid& grid) {
  fill_cells(grid, 0, 0, grid.width() - 1, 0);
  fill_cells(grid, 0, grid.height() - 1, grid.width() - 1, grid.height() - 1);
  fill_cells(grid, 0, 0, 0, grid.height() - 1);
  fill_cells(grid, grid.width() - 1, 0, grid.width() - 1, grid.height() - 1);
}

}  // namespace mobot::sim::testing
