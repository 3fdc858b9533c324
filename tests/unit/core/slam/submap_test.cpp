#include "core/slam/submap.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

namespace mobot::slam {
namespace {

TEST(Submap, PutsEveryScanAtItsPoseAndClipsToTheRegion) {
  const std::vector<geometry::Point2D> points{{1.0, 0.0}};
  const std::vector<SubmapScan> scans{{{0.0, 0.0, 0.0}, points},
                                      {{2.0, 0.0, std::acos(-1.0) / 2.0}, points}};
  const Submap whole(scans, {});
  EXPECT_EQ(whole.point_count(), 2U);
  EXPECT_NEAR(whole.field().interpolate(1.0, 0.0).value, 1.0, 0.05);
  EXPECT_NEAR(whole.field().interpolate(2.0, 1.0).value, 1.0, 0.05);
  const Submap clipped(scans, {}, MapBox{0.5, -0.5, 1.5, 0.5});
  EXPECT_EQ(clipped.point_count(), 1U);
  EXPECT_NEAR(clipped.field().interpolate(1.0, 0.0).value, 1.0, 0.05);
  EXPECT_LT(clipped.field().width() * clipped.field().limits().resolution_m, 1.6);
}

TEST(Submap, EmptyForNoPointsOrAFarRegionAndRejectsBadOptions) {
  const std::vector<geometry::Point2D> points{{1.0, 0.0}};
  const std::vector<SubmapScan> scans{{{0.0, 0.0, 0.0}, points}};
  EXPECT_TRUE(Submap({}, {}).field().empty());
  EXPECT_TRUE(Submap(scans, {}, MapBox{10, 10, 11, 11}).field().empty());
  const std::vector<SubmapScan> bad{{{std::nan(""), 0.0, 0.0}, points}};
  EXPECT_TRUE(Submap(bad, {}).field().empty());
  EXPECT_THROW(Submap(scans, {0.0, 0.07}), std::invalid_argument);
  EXPECT_THROW(Submap(scans, {0.05, -1.0}), std::invalid_argument);
}

TEST(Submap, BoxAroundCoversThePosedPointsAndTheOrigin) {
  const std::vector<geometry::Point2D> points{{1.0, 0.0}, {0.0, 2.0}};
  const MapBox box = box_around(points, {1.0, 1.0, 0.0}, 0.5);
  EXPECT_DOUBLE_EQ(box.min_x_m, 0.5);
  EXPECT_DOUBLE_EQ(box.max_x_m, 2.5);
  EXPECT_DOUBLE_EQ(box.min_y_m, 0.5);
  EXPECT_DOUBLE_EQ(box.max_y_m, 3.5);
}

}  // namespace
}  // namespace mobot::slam
