#include "drivers/sim/camera_noise.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace mobot::sim {
namespace {

TEST(CameraNoise, PixelNoiseHasTheConfiguredSpreadAndNoBias) {
  CameraNoise noise({0.0, 1.0, 3.0, 0.0});
  std::mt19937_64 rng(1);
  cv::Mat image(240, 320, CV_8UC3, cv::Scalar(100, 128, 160));
  const cv::Mat clean = image.clone();
  noise.apply(image, rng);
  cv::Mat difference;
  cv::subtract(image, clean, difference, cv::noArray(), CV_32F);
  cv::Scalar mean;
  cv::Scalar deviation;
  cv::meanStdDev(difference.reshape(1), mean, deviation);
  EXPECT_NEAR(mean[0], 0.0, 0.05);
  EXPECT_NEAR(deviation[0], 3.0, 0.1);
}

TEST(CameraNoise, NoneLeavesTheImageAlone) {
  const CameraNoise noise = CameraNoise::none();
  std::mt19937_64 rng(1);
  cv::Mat image(10, 10, CV_8UC3, cv::Scalar(10, 20, 30));
  const cv::Mat clean = image.clone();
  noise.apply(image, rng);
  EXPECT_EQ(cv::norm(image, clean, cv::NORM_INF), 0.0);
}

TEST(CameraNoise, TheGainDriftsSlowlyAndScalesTheImage) {
  CameraNoise noise({0.1, 10.0, 0.0, 0.0});
  std::mt19937_64 rng(2);
  noise.start(rng);
  double previous = noise.gain();
  double lowest = previous;
  double highest = previous;
  for (int frame = 0; frame < 3000; ++frame) {
    noise.advance(1.0 / 15.0, rng);
    // Frame to frame a step of sd 0.1 sqrt(2 dt / tau) = 0.012: slow.
    EXPECT_LT(std::fabs(noise.gain() - previous), 0.06);
    previous = noise.gain();
    lowest = std::min(lowest, previous);
    highest = std::max(highest, previous);
  }
  EXPECT_GT(highest - lowest, 0.25);  // over 200 s it does wander
  cv::Mat image(4, 4, CV_8UC3, cv::Scalar(100, 100, 100));
  noise.apply(image, rng);
  EXPECT_NEAR(image.at<cv::Vec3b>(0, 0)[0], 100.0 * noise.gain(), 0.51);
}

TEST(CameraNoise, RejectsBadOptionsNamingThem) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(CameraNoise({-0.1, 1.0, 1.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(CameraNoise({0.1, 0.0, 1.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(CameraNoise({0.1, 1.0, nan, 0.0}), std::invalid_argument);
  try {
    CameraNoise({0.1, 1.0, 1.0, -1.0});
    FAIL();
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("blur_sigma_px"), std::string::npos);
  }
}

}  // namespace
}  // namespace mobot::sim
