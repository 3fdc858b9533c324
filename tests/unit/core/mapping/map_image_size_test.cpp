#include "core/mapping/map_image_size.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/mapping/map_image_codec.h"

namespace mobot::mapping {
namespace {

std::vector<std::uint8_t> bytes(const std::string& text) { return {text.begin(), text.end()}; }

TEST(MapImageSize, ReadsAPngsIhdr) {
  const OccupancyGrid grid(7, 3, 0.05, {});
  const auto size = read_map_image_size(encode_map_png(grid));
  ASSERT_TRUE(size.has_value());
  EXPECT_EQ(size->width, 7U);
  EXPECT_EQ(size->height, 3U);
}

TEST(MapImageSize, ReadsPgmHeadersWithCommentsAndAnyWhitespace) {
  const OccupancyGrid grid(5, 4, 0.05, {});
  const auto encoded = read_map_image_size(encode_map_pgm(grid));
  ASSERT_TRUE(encoded.has_value());
  EXPECT_EQ(encoded->pixels(), 20U);
  const auto commented = read_map_image_size(bytes("P5\n# made by hand\n12\t# w\n 34\n255\n"));
  ASSERT_TRUE(commented.has_value());
  EXPECT_EQ(commented->width, 12U);
  EXPECT_EQ(commented->height, 34U);
  const auto plain = read_map_image_size(bytes("P2 3 2 255 0 0 0 0 0 0"));
  ASSERT_TRUE(plain.has_value());
  EXPECT_EQ(plain->pixels(), 6U);
}

TEST(MapImageSize, AgreesWithTheDecoderOnOddHeaders) {
  // Found by tests/fuzz/map_image_fuzz.cpp: OpenCV consumes the byte that ends a number, so the
  // '#' after the width starts no comment and the height is 3, not 255.
  std::vector<std::uint8_t> image = bytes("P5\n4#3\n255\n");
  image.resize(image.size() + 12, 254);
  const auto size = read_map_image_size(image);
  ASSERT_TRUE(size.has_value());
  EXPECT_EQ(size->width, 4U);
  EXPECT_EQ(size->height, 3U);
  const OccupancyGrid grid = decode_map_image(image, 0.05, {}, {}, 100);
  EXPECT_EQ(grid.width(), 4);
  EXPECT_EQ(grid.height(), 3);
}

TEST(MapImageSize, CapsHugeDimensionsWithoutOverflow) {
  const auto huge = read_map_image_size(bytes("P5 99999999999999999999999 99999999999 255\n"));
  ASSERT_TRUE(huge.has_value());
  EXPECT_EQ(huge->width, std::uint64_t{1} << 31);
  EXPECT_EQ(huge->pixels(), std::uint64_t{1} << 62);
}

TEST(MapImageSize, OtherFormatsAndBrokenHeadersHaveNoSize) {
  for (const std::string& text :
       {std::string(), std::string("P5"), std::string("P5 12"), std::string("P512 12 255"),
        std::string("P6 2 2 255\n"), std::string("P5 x 2 255"), std::string("P5#c\n1 1 255"),
        std::string("\x89PNG\r\n\x1a\n"), std::string("GIF89a"), std::string("\xFF\xD8\xFF\xE0")}) {
    EXPECT_FALSE(read_map_image_size(bytes(text)).has_value()) << text;
  }
}

TEST(MapImageSize, TheDecoderRefusesAnImageDeclaredTooLargeBeforeDecodingIt) {
  // A 100000 x 100000 PGM header with no pixels: refused for its size, not for the missing data.
  try {
    decode_map_image(bytes("P5 100000 100000 255\n"), 0.05, {}, {}, 25'000'000);
    FAIL() << "accepted";
  } catch (const MapImageError& error) {
    EXPECT_NE(std::string(error.what()).find("limit"), std::string::npos) << error.what();
  }
  const std::vector<std::uint8_t> tiff{'I', 'I', 42, 0, 8, 0, 0, 0};
  EXPECT_THROW(decode_map_image(tiff, 0.05, {}, {}, 100), MapImageError);
}

}  // namespace
}  // namespace mobot::mapping
