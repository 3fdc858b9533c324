// Bearing data association: nearest first, nothing used twice, the gate, the wrap at +-pi.
#include "core/vision/bearing_match.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace mobot::vision {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(MatchBearings, PairsEachDetectionWithItsNearestPrediction) {
  const std::vector<double> detected{0.53, -1.98};
  const std::vector<double> predicted{-2.0, 1.4, 0.5};
  const std::vector<BearingMatch> matches = match_bearings(detected, predicted, 0.1);
  ASSERT_EQ(matches.size(), 2U);
  // Smallest |innovation| first.
  EXPECT_EQ(matches[0].detected_index, 1U);
  EXPECT_EQ(matches[0].predicted_index, 0U);
  EXPECT_NEAR(matches[0].innovation_rad, 0.02, 1e-12);
  EXPECT_EQ(matches[1].detected_index, 0U);
  EXPECT_EQ(matches[1].predicted_index, 2U);
  EXPECT_NEAR(matches[1].innovation_rad, 0.03, 1e-12);
}

TEST(MatchBearings, NeverUsesADetectionOrAPredictionTwice) {
  // Two predictions near one detection: only the closer gets it.
  const std::vector<double> one{1.0};
  const std::vector<double> two{1.03, 0.98};
  std::vector<BearingMatch> matches = match_bearings(one, two, 0.1);
  ASSERT_EQ(matches.size(), 1U);
  EXPECT_EQ(matches[0].predicted_index, 1U);
  // Two detections near one prediction: likewise.
  matches = match_bearings(two, one, 0.1);
  ASSERT_EQ(matches.size(), 1U);
  EXPECT_EQ(matches[0].detected_index, 1U);
  // A crossing: greedy takes the closest pair, the other detection takes what is left.
  const std::vector<double> detected{0.10, 0.16};
  const std::vector<double> predicted{0.15, 0.05};
  matches = match_bearings(detected, predicted, 0.1);
  ASSERT_EQ(matches.size(), 2U);
  EXPECT_EQ(matches[0].detected_index, 1U);
  EXPECT_EQ(matches[0].predicted_index, 0U);
  EXPECT_EQ(matches[1].detected_index, 0U);
  EXPECT_EQ(matches[1].predicted_index, 1U);
}

TEST(MatchBearings, WrapsAcrossPi) {
  const std::vector<double> detected{kPi - 0.01};
  const std::vector<double> predicted{-kPi + 0.02};
  const std::vector<BearingMatch> matches = match_bearings(detected, predicted, 0.05);
  ASSERT_EQ(matches.size(), 1U);
  EXPECT_NEAR(matches[0].innovation_rad, -0.03, 1e-12);
}

TEST(MatchBearings, GateAndBadInput) {
  const std::vector<double> detected{0.0, std::nan(""), 2.0};
  const std::vector<double> predicted{0.2, 1.0, std::numeric_limits<double>::infinity()};
  EXPECT_TRUE(match_bearings(detected, predicted, 0.1).empty());
  EXPECT_EQ(match_bearings(detected, predicted, 0.25).size(), 1U);
  EXPECT_TRUE(match_bearings(detected, predicted, -1.0).empty());
  EXPECT_TRUE(match_bearings(detected, predicted, std::nan("")).empty());
  EXPECT_TRUE(match_bearings({}, predicted, 1.0).empty());
  EXPECT_TRUE(match_bearings(detected, {}, 1.0).empty());
}

}  // namespace
}  // namespace mobot::vision
