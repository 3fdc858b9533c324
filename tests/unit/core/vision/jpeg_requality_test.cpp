// requality_jpeg: a JPEG compressed again keeps its size in pixels and shrinks with the quality;
// bytes that are no image and qualities outside 1..100 give nothing.
#include "core/vision/jpeg_requality.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

namespace mobot::vision {
namespace {

std::vector<std::uint8_t> textured_jpeg(int quality) {
  cv::Mat pixels(120, 160, CV_8UC3);
  cv::randu(pixels, cv::Scalar::all(0), cv::Scalar::all(255));
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", pixels, jpeg, {cv::IMWRITE_JPEG_QUALITY, quality});
  return jpeg;
}

TEST(JpegRequality, KeepsTheSizeAndShrinksWithTheQuality) {
  const auto original = textured_jpeg(95);
  const auto at_50 = requality_jpeg(original, 50);
  const auto at_10 = requality_jpeg(original, 10);
  ASSERT_TRUE(at_50.has_value());
  ASSERT_TRUE(at_10.has_value());
  EXPECT_LT(at_50->size(), original.size());
  EXPECT_LT(at_10->size(), at_50->size());
  const cv::Mat decoded = cv::imdecode(*at_10, cv::IMREAD_UNCHANGED);
  EXPECT_EQ(decoded.cols, 160);
  EXPECT_EQ(decoded.rows, 120);
  EXPECT_EQ(decoded.channels(), 3);
}

TEST(JpegRequality, GarbageAndBadQualitiesGiveNothing) {
  const auto original = textured_jpeg(80);
  EXPECT_FALSE(requality_jpeg(original, 0).has_value());
  EXPECT_FALSE(requality_jpeg(original, 101).has_value());
  EXPECT_FALSE(requality_jpeg({}, 50).has_value());
  const std::vector<std::uint8_t> garbage(4096, 0x5A);
  EXPECT_FALSE(requality_jpeg(garbage, 50).has_value());
  std::vector<std::uint8_t> truncated(original.begin(), original.begin() + 20);
  EXPECT_FALSE(requality_jpeg(truncated, 50).has_value());
}

}  // namespace
}  // namespace mobot::vision
