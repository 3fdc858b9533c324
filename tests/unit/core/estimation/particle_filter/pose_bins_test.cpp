#include "core/estimation/particle_filter/pose_bins.h"

#include <gtest/gtest.h>

#include <numbers>
#include <vector>

namespace mobot::estimation {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(PoseBins, BinsPositionByFloorAndHeadingFromMinusPi) {
  const PoseBinSize size;  // 0.5 m, 10 deg
  EXPECT_EQ(theta_bin_count(size), 36);
  EXPECT_EQ(pose_bin({0.1, 0.6, -kPi + 1e-6}, size), (PoseBin{0, 1, 0}));
  EXPECT_EQ(pose_bin({-0.1, -0.6, 0.0}, size), (PoseBin{-1, -2, 18}));
  // +pi and -pi are the same heading, the same bin; headings outside (-pi, pi] are wrapped.
  EXPECT_EQ(pose_bin({0.0, 0.0, kPi}, size), pose_bin({0.0, 0.0, -kPi}, size));
  EXPECT_EQ(pose_bin({0.0, 0.0, 0.05 + 2 * kPi}, size), pose_bin({0.0, 0.0, 0.05}, size));
  EXPECT_EQ(pose_bin({0.0, 0.0, kPi - 1e-6}, size).theta, 35);
  // A bin size that does not divide the circle leaves a narrower last bin.
  EXPECT_EQ(theta_bin_count({0.5, 0.25}), 26);
}

TEST(PoseBins, KeysAreDistinctForNeighbouringAndNegativeBins) {
  std::vector<std::uint64_t> keys;
  for (int x = -2; x <= 2; ++x) {
    for (int y = -2; y <= 2; ++y) {
      for (int t = 0; t < 3; ++t) keys.push_back(bin_key({x, y, t}));
    }
  }
  std::sort(keys.begin(), keys.end());
  EXPECT_EQ(std::unique(keys.begin(), keys.end()), keys.end());
}

TEST(PoseBins, CountsOccupiedBins) {
  const PoseBinSize size;
  const std::vector<WeightedPose> poses = {{{0.1, 0.1, 0.0}, 1.0},
                                           {{0.2, 0.3, 0.01}, 1.0},  // same bin
                                           {{0.6, 0.1, 0.0}, 1.0},
                                           {{0.1, 0.1, 1.0}, 1.0}};
  EXPECT_EQ(count_occupied_bins(poses, size), 3U);
  EXPECT_EQ(count_occupied_bins({}, size), 0U);
}

}  // namespace
}  // namespace mobot::estimation
