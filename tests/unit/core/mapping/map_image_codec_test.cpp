#include "core/mapping/map_image_codec.h"

#include <gtest/gtest.h>

#include <string>

namespace mobot::mapping {
namespace {

std::vector<std::uint8_t> pgm(int width, int height, const std::vector<std::uint8_t>& pixels) {
  const std::string header =
      "P5\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n";
  std::vector<std::uint8_t> bytes(header.begin(), header.end());
  bytes.insert(bytes.end(), pixels.begin(), pixels.end());
  return bytes;
}

TEST(MapImageCodec, DecodesTrinaryAndFlipsRows) {
  // Top row: occupied, unknown; bottom row: free, free.
  const auto image = pgm(2, 2, {0, 205, 254, 255});
  const OccupancyGrid grid = decode_map_image(image, 0.1, {1, 2, 0}, {}, 100);
  ASSERT_EQ(grid.width(), 2);
  ASSERT_EQ(grid.height(), 2);
  EXPECT_EQ(grid.at({0, 1}), OccupancyGrid::kOccupied);
  EXPECT_EQ(grid.at({1, 1}), OccupancyGrid::kUnknown);
  EXPECT_EQ(grid.at({0, 0}), OccupancyGrid::kFree);
  EXPECT_EQ(grid.at({1, 0}), OccupancyGrid::kFree);
  EXPECT_DOUBLE_EQ(grid.resolution_m(), 0.1);
  EXPECT_EQ(grid.origin(), (geometry::Pose2D{1, 2, 0}));
}

TEST(MapImageCodec, NegateAndThresholdsFollowMapServer) {
  const auto image = pgm(3, 1, {0, 128, 255});
  MapImageOptions negated;
  negated.negate = true;
  const OccupancyGrid grid = decode_map_image(image, 0.05, {}, negated, 100);
  EXPECT_EQ(grid.at({0, 0}), OccupancyGrid::kFree);
  EXPECT_EQ(grid.at({1, 0}), OccupancyGrid::kUnknown);
  EXPECT_EQ(grid.at({2, 0}), OccupancyGrid::kOccupied);
  MapImageOptions strict;
  strict.occupied_thresh = 0.4;
  const OccupancyGrid grey = decode_map_image(image, 0.05, {}, strict, 100);
  EXPECT_EQ(grey.at({1, 0}), OccupancyGrid::kOccupied);
}

TEST(MapImageCodec, PgmAndPngRoundTrip) {
  OccupancyGrid grid(5, 3, 0.05, {-2, -1, 0}, OccupancyGrid::kFree);
  grid.set({0, 0}, OccupancyGrid::kOccupied);
  grid.set({4, 2}, OccupancyGrid::kUnknown);
  for (const auto& bytes : {encode_map_pgm(grid), encode_map_png(grid)}) {
    const OccupancyGrid back = decode_map_image(bytes, 0.05, grid.origin(), {}, 100);
    EXPECT_EQ(back.cells(), grid.cells());
  }
}

TEST(MapImageCodec, RejectsGarbageEmptyAndOversizedImages) {
  const std::vector<std::uint8_t> garbage{'n', 'o', 't', ' ', 'a', 'n', ' ', 'i', 'm', 'g'};
  EXPECT_THROW(decode_map_image(garbage, 0.05, {}, {}, 100), MapImageError);
  EXPECT_THROW(decode_map_image({}, 0.05, {}, {}, 100), MapImageError);
  EXPECT_THROW(
      decode_map_image(pgm(20, 20, std::vector<std::uint8_t>(400, 255)), 0.05, {}, {}, 100),
      MapImageError);
  EXPECT_THROW(decode_map_image(pgm(1, 1, {255}), 0.0, {}, {}, 100), MapImageError);
}

TEST(MapImageCodec, AHeaderOpenCvRefusesIsAMapImageError) {
  // Found by tests/fuzz/map_image_fuzz.cpp: OpenCV throws its own exception for a side over 2^20
  // pixels (within the cell limit here), which reached the REST client as a 500.
  const std::string text = "P2\n3 5555551\n255\n0 0 0\n";
  const std::vector<std::uint8_t> bytes(text.begin(), text.end());
  EXPECT_THROW(decode_map_image(bytes, 0.05, {}, {}, 25'000'000), MapImageError);
}

TEST(MapImageCodec, YamlNamesImageResolutionAndOrigin) {
  const OccupancyGrid grid(2, 2, 0.05, {-3.5, 1.25, 0});
  const std::string yaml = encode_map_yaml(grid, "map.pgm");
  EXPECT_NE(yaml.find("image: map.pgm"), std::string::npos);
  EXPECT_NE(yaml.find("resolution: 0.05"), std::string::npos);
  EXPECT_NE(yaml.find("origin: [-3.5, 1.25, 0]"), std::string::npos);
}

}  // namespace
}  // namespace mobot::mapping
