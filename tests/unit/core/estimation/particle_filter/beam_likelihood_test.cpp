#include "core/estimation/particle_filter/beam_likelihood.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "tests/unit/core/estimation/particle_filter/pf_world.h"

namespace mobot::estimation {
namespace {

using geometry::Pose2D;
using mapping::OccupancyGrid;
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNanF = std::numeric_limits<float>::quiet_NaN();

msgs::LaserScan fan(int beams, float range_m) {
  msgs::LaserScan scan;
  scan.angle_min_rad = static_cast<float>(-std::numbers::pi / 2.0);
  scan.angle_increment_rad = static_cast<float>(std::numbers::pi / (beams - 1));
  scan.range_min_m = 0.1F;
  scan.range_max_m = 30.0F;
  scan.ranges_m.assign(static_cast<std::size_t>(beams), range_m);
  return scan;
}

std::shared_ptr<const LikelihoodField> single_obstacle_field() {
  OccupancyGrid grid(100, 100, 0.05, {}, OccupancyGrid::kFree);
  grid.set({60, 50}, OccupancyGrid::kOccupied);  // centre (3.025, 2.525)
  return std::make_shared<const LikelihoodField>(grid, LikelihoodFieldOptions{2.0});
}

TEST(BeamLikelihood, ThinsTheScanEvenlyToSixtyBeamsFirstAndLastIncluded) {
  const BeamLikelihood model(single_obstacle_field());
  const msgs::LaserScan scan = fan(181, 2.0F);
  const PreparedScan prepared = model.prepare(scan);
  ASSERT_EQ(prepared.endpoints_in_base.size(), 60U);
  EXPECT_NEAR(prepared.endpoints_in_base.front().x, 0.0, 1e-6);
  EXPECT_NEAR(prepared.endpoints_in_base.front().y, -2.0, 1e-6);
  EXPECT_NEAR(prepared.endpoints_in_base.back().x, 0.0, 1e-6);
  EXPECT_NEAR(prepared.endpoints_in_base.back().y, 2.0, 1e-6);
  // z_rand / range_max with AMCL's 6 m cap below the scan's 30 m.
  EXPECT_DOUBLE_EQ(prepared.rand_term, 0.5 / 6.0);
  // A scan with fewer beams than the limit keeps them all.
  EXPECT_EQ(model.prepare(fan(20, 2.0F)).endpoints_in_base.size(), 20U);
}

TEST(BeamLikelihood, SkipsTheBeamsAmclIgnores) {
  BeamLikelihoodOptions options;
  options.max_beams = 7;
  options.no_return_beams = false;
  const BeamLikelihood model(single_obstacle_field(), options);
  msgs::LaserScan scan = fan(7, 2.0F);
  scan.ranges_m = {2.0F, kNanF, 6.0F, 7.5F, 0.05F, kInf, 1.0F};  // 6 m: at the range cap
  const PreparedScan prepared = model.prepare(scan);
  ASSERT_EQ(prepared.endpoints_in_base.size(), 2U);
  EXPECT_TRUE(prepared.free_ray_ends_in_base.empty());
  EXPECT_EQ(prepared.beam_count(), 2U);
  // The scan's own range_max is the cap when it is the smaller one.
  scan.range_max_m = 1.5F;
  const PreparedScan short_range = model.prepare(scan);
  EXPECT_EQ(short_range.endpoints_in_base.size(), 1U);
  EXPECT_DOUBLE_EQ(short_range.rand_term, 0.5 / 1.5);
}

TEST(BeamLikelihood, KeepsTheBeamsWithoutAReturnAsFreeRaysShortOfTheRange) {
  BeamLikelihoodOptions options;
  options.max_beams = 7;
  options.no_return_clearance_rad = 0.0;
  const BeamLikelihood model(single_obstacle_field(), options);
  msgs::LaserScan scan = fan(7, 2.0F);
  scan.ranges_m = {2.0F, kNanF, 6.0F, 7.5F, 0.05F, kInf, 1.0F};
  const PreparedScan prepared = model.prepare(scan);
  EXPECT_EQ(prepared.endpoints_in_base.size(), 2U);
  // At the cap, beyond it and infinite; NaN and too near stay out.
  ASSERT_EQ(prepared.free_ray_ends_in_base.size(), 3U);
  EXPECT_EQ(prepared.beam_count(), 5U);
  for (const geometry::Point2D& end : prepared.free_ray_ends_in_base) {
    EXPECT_NEAR(std::hypot(end.x, end.y), 6.0 - 0.3, 1e-6);
  }
  // The third beam looks at -30 deg.
  EXPECT_NEAR(std::atan2(prepared.free_ray_ends_in_base[0].y, prepared.free_ray_ends_in_base[0].x),
              -std::numbers::pi / 6.0, 1e-6);
  // Free rays alone weigh nothing: a lidar with no return at all is blinded.
  scan.ranges_m.assign(7, kInf);
  const PreparedScan blind = model.prepare(scan);
  EXPECT_TRUE(blind.empty());
}

TEST(BeamLikelihood, OnlyBeamsWellInsideAnOpenSectorBecomeFreeRays) {
  BeamLikelihoodOptions options;  // 3 deg either side must be open too
  options.max_beams = 181;
  const BeamLikelihood model(single_obstacle_field(), options);
  msgs::LaserScan scan = fan(181, 2.0F);                            // 1 deg apart
  for (std::size_t i = 80; i <= 100; ++i) scan.ranges_m[i] = kInf;  // an open sector of 21 deg
  scan.ranges_m[0] = kInf;  // open at the scan's edge: nothing known beyond it
  const PreparedScan prepared = model.prepare(scan);
  // Beams 83..97: three open beams either side.
  EXPECT_EQ(prepared.free_ray_ends_in_base.size(), 10U);  // 15, thinned to max_no_return_beams
  for (const geometry::Point2D& end : prepared.free_ray_ends_in_base) {
    EXPECT_LE(std::abs(std::atan2(end.y, end.x)), 7.0 * std::numbers::pi / 180.0 + 1e-6);
  }
  // A NaN beside an open beam is no evidence that the neighbourhood is open.
  scan.ranges_m[90] = kNanF;
  options.max_no_return_beams = 100;
  const BeamLikelihood all(single_obstacle_field(), options);
  EXPECT_EQ(all.prepare(scan).free_ray_ends_in_base.size(), 8U);  // 83..86 and 94..97
  // A full circle wraps round: the first beam's neighbours are the last ones.
  msgs::LaserScan circle = fan(360, 2.0F);
  circle.angle_min_rad = 0.0F;
  circle.angle_increment_rad = static_cast<float>(2.0 * std::numbers::pi / 360.0);
  for (const std::size_t i : {357U, 358U, 359U, 0U, 1U, 2U, 3U}) circle.ranges_m[i] = kInf;
  const PreparedScan round = all.prepare(circle);
  ASSERT_EQ(round.free_ray_ends_in_base.size(), 1U);
  EXPECT_NEAR(round.free_ray_ends_in_base[0].y, 0.0, 1e-6);
}

TEST(BeamLikelihood, SegmentFreeStopsAtOccupiedCellsOnly) {
  OccupancyGrid grid(100, 100, 0.05, {}, OccupancyGrid::kFree);
  for (int y = 0; y < 100; ++y) grid.set({50, y}, OccupancyGrid::kOccupied);  // a wall at x 2.5
  grid.set({10, 10}, OccupancyGrid::kUnknown);
  const BeamLikelihood model(std::make_shared<const LikelihoodField>(grid));
  EXPECT_FALSE(model.segment_free({0.5, 1.0}, {4.5, 1.0}));
  // Diagonally through the one-cell wall, at every offset within a cell.
  for (double offset = 0.0; offset < 0.05; offset += 0.007) {
    EXPECT_FALSE(model.segment_free({0.5 + offset, 0.3}, {4.5, 4.1 + offset})) << offset;
  }
  // Beside the wall, along it, and ending just short of it.
  EXPECT_TRUE(model.segment_free({2.3, 0.2}, {2.3, 4.8}));
  // Along it in the next cell is as good as into it.
  EXPECT_FALSE(model.segment_free({2.47, 0.2}, {2.47, 4.8}));
  EXPECT_TRUE(model.segment_free({0.5, 1.0}, {2.4, 1.0}));
  // Unknown cells are not obstacles; off the grid there is nothing known.
  EXPECT_TRUE(model.segment_free({0.0, 0.0}, {1.0, 1.0}));
  EXPECT_TRUE(model.segment_free({-3.0, 1.0}, {-1.0, 1.0}));
  EXPECT_TRUE(model.segment_free({3.0, 1.0}, {9.0, 1.0}));
  EXPECT_TRUE(model.segment_free({1.0, 1.0}, {1.0, 1.0}));
}

TEST(BeamLikelihood, PutsTheEndPointsInTheBaseFrameThroughTheMounting) {
  const BeamLikelihood model(single_obstacle_field());
  msgs::LaserScan scan = fan(3, 1.0F);
  scan.sensor_in_base = {0.3, -0.1, std::numbers::pi / 2.0};
  const PreparedScan prepared = model.prepare(scan);
  ASSERT_EQ(prepared.endpoints_in_base.size(), 3U);
  // The middle beam looks along the sensor's x axis, which is the base's y axis.
  EXPECT_NEAR(prepared.endpoints_in_base[1].x, 0.3, 1e-6);
  EXPECT_NEAR(prepared.endpoints_in_base[1].y, 0.9, 1e-6);
  EXPECT_NEAR(prepared.endpoints_in_base[0].x, 1.3, 1e-6);
  EXPECT_NEAR(prepared.endpoints_in_base[0].y, -0.1, 1e-6);
}

BeamLikelihoodOptions with(BeamCombination combination) {
  BeamLikelihoodOptions options;
  options.combination = combination;
  return options;
}

// One beam ending on the obstacle, 0.3 m from it, and 2 m (the cap) from it.
struct OneBeam {
  PreparedScan scan{{{1.0, 0.0}}, 0.5 / 6.0, {}, {}};
  double on = 0.5 + 0.5 / 6.0;  // p = z_hit + z_rand / range_max
  double near = 0.5 * std::exp(-0.09 / 0.08) + 0.5 / 6.0;
  double off = 0.5 * std::exp(-4.0 / 0.08) + 0.5 / 6.0;
  Pose2D on_pose{2.025, 2.525, 0.0};
  Pose2D near_pose{1.725, 2.525, 0.0};
};

TEST(BeamLikelihood, CubedSumIsAmclsLikelihoodField) {
  const BeamLikelihood model(single_obstacle_field(), with(BeamCombination::kCubedSum));
  const OneBeam b;
  EXPECT_NEAR(model.log_likelihood(b.scan, b.on_pose), std::log(1.0 + std::pow(b.on, 3)), 1e-6);
  EXPECT_NEAR(model.log_likelihood(b.scan, b.near_pose), std::log(1.0 + std::pow(b.near, 3)), 1e-6);
  EXPECT_NEAR(model.log_likelihood(b.scan, {-5.0, -5.0, 0.0}), std::log(1.0 + std::pow(b.off, 3)),
              1e-9);
  // The heading turns the beam: facing away, it ends 2 m from the obstacle.
  EXPECT_NEAR(model.log_likelihood(b.scan, {2.025, 2.525, std::numbers::pi}),
              std::log(1.0 + std::pow(b.off, 3)), 1e-6);
  // The agreement is the mean p^3.
  EXPECT_NEAR(model.beam_agreement(std::log(1.0 + 2 * 0.125), 2), 0.125, 1e-12);
}

TEST(BeamLikelihood, ProductIsAmclsLikelihoodFieldProb) {
  const BeamLikelihood model(single_obstacle_field(), with(BeamCombination::kProduct));
  OneBeam b;
  EXPECT_NEAR(model.log_likelihood(b.scan, b.on_pose), std::log(b.on), 1e-6);
  EXPECT_NEAR(model.log_likelihood(b.scan, b.near_pose), std::log(b.near), 1e-6);
  EXPECT_NEAR(model.log_likelihood(b.scan, {-5.0, -5.0, 0.0}), std::log(b.off), 1e-9);
  // Two beams multiply; the agreement is their geometric mean.
  b.scan.endpoints_in_base.push_back({1.3, 0.0});  // 0.3 m beyond the obstacle
  const double both = model.log_likelihood(b.scan, b.on_pose);
  EXPECT_NEAR(both, std::log(b.on) + std::log(b.near), 1e-6);
  EXPECT_NEAR(model.beam_agreement(both, 2), std::sqrt(b.on * b.near), 1e-6);
  // A scan with a shorter range than the model's takes the slow path with its own rand term.
  PreparedScan short_range{{{1.0, 0.0}}, 0.5 / 2.0, {}, {}};
  EXPECT_NEAR(model.log_likelihood(short_range, b.on_pose), std::log(0.5 + 0.25), 1e-6);
}

TEST(BeamLikelihood, AFreeRayAcrossAnObstacleScoresAsAMiss) {
  for (const auto combination : {BeamCombination::kCubedSum, BeamCombination::kProduct}) {
    BeamLikelihoodOptions options = with(combination);
    options.no_return_weight = 1.0;  // a ray counts as a return
    const BeamLikelihood model(single_obstacle_field(), options);
    const double clear = 0.5 + 0.5 / 6.0;  // p of a hit
    const double blocked = 0.5 / 6.0;      // p of a miss
    // One return 1 m ahead, and a ray without a return along the base's +y axis.
    const PreparedScan returns_only{{{1.0, 0.0}}, 0.5 / 6.0, {0.0, 0.0}, {}};
    PreparedScan scan = returns_only;
    scan.free_ray_ends_in_base = {{0.0, 5.7}};
    // What the free ray adds to the log-likelihood, given the return's own term.
    const auto added = [&](const Pose2D& pose) {
      const double with_ray = model.log_likelihood(scan, pose);
      const double without = model.log_likelihood(returns_only, pose);
      return combination == BeamCombination::kProduct
                 ? with_ray - without
                 : std::log(std::expm1(with_ray) - std::expm1(without));
    };
    const double power = combination == BeamCombination::kProduct ? 1.0 : 3.0;
    // From below the obstacle (centre 3.025, 2.525) the ray runs through it.
    EXPECT_NEAR(added({3.025, 0.525, 0.0}), power * std::log(blocked), 1e-6);
    // A metre to its side it passes clear, off the grid at y 5.
    EXPECT_NEAR(added({2.025, 0.525, 0.0}), power * std::log(clear), 1e-6);
    // From above, pointing away from it.
    EXPECT_NEAR(added({3.025, 3.525, 0.0}), power * std::log(clear), 1e-6);
  }
}

TEST(BeamLikelihood, AFreeRayCountsForItsWeightOfAReturn) {
  BeamLikelihoodOptions options = with(BeamCombination::kProduct);
  options.no_return_weight = 0.3;
  const BeamLikelihood model(single_obstacle_field(), options);
  const PreparedScan returns_only{{{1.0, 0.0}}, 0.5 / 6.0, {0.0, 0.0}, {}};
  PreparedScan scan = returns_only;
  scan.free_ray_ends_in_base = {{0.0, 5.7}, {0.0, 5.7}};
  const Pose2D through{3.025, 0.525, 0.0};
  EXPECT_NEAR(model.log_likelihood(scan, through) - model.log_likelihood(returns_only, through),
              2 * 0.3 * std::log(0.5 / 6.0), 1e-6);
  const Pose2D beside{2.025, 0.525, 0.0};
  EXPECT_NEAR(model.log_likelihood(scan, beside) - model.log_likelihood(returns_only, beside),
              2 * 0.3 * std::log(0.5 + 0.5 / 6.0), 1e-6);
  // A pose hopeless even with its rays clear gets them as blocked, unwalked: never more than it
  // would have had.
  const double walked = model.log_likelihood(scan, beside);
  EXPECT_NEAR(model.log_likelihood(scan, beside, walked + 100.0),
              model.log_likelihood(returns_only, beside) + 2 * 0.3 * std::log(0.5 / 6.0), 1e-6);
  EXPECT_EQ(model.log_likelihood(scan, beside, walked - 100.0), walked);
}

TEST(BeamLikelihood, NothingToWeighIsNeutral) {
  for (const auto combination : {BeamCombination::kCubedSum, BeamCombination::kProduct}) {
    const BeamLikelihood model(single_obstacle_field(), with(combination));
    const OneBeam b;
    EXPECT_EQ(model.log_likelihood(PreparedScan{}, {2.0, 2.0, 0.0}), 0.0);
    EXPECT_EQ(model.log_likelihood(b.scan, {std::numeric_limits<double>::quiet_NaN(), 2.0, 0.0}),
              0.0);
    EXPECT_EQ(model.beam_agreement(1.0, 0), 0.0);
  }
  // z_rand 0 and a beam far from everything: very unlikely, never -inf.
  BeamLikelihoodOptions options = with(BeamCombination::kProduct);
  options.z_rand = 0.0;
  options.sigma_hit_m = 0.01;
  const BeamLikelihood model(single_obstacle_field(), options);
  EXPECT_TRUE(std::isfinite(model.log_likelihood(OneBeam{}.scan, {-5.0, -5.0, 0.0})));
}

TEST(BeamLikelihood, PeaksAtTheTruePoseInTheRoom) {
  const pf_world::Room room = pf_world::asymmetric_room();
  const auto field = std::make_shared<const LikelihoodField>(pf_world::room_grid(room));
  for (const auto combination : {BeamCombination::kCubedSum, BeamCombination::kProduct}) {
    const BeamLikelihood model(field, with(combination));
    const Pose2D truth{3.5, 3.0, 0.4};
    const PreparedScan scan = model.prepare(pf_world::room_scan(room, truth, nullptr));
    ASSERT_GT(scan.endpoints_in_base.size(), 40U);
    const double at_truth = model.log_likelihood(scan, truth);
    for (const Pose2D offset :
         {Pose2D{0.2, 0.0, 0.0}, {0.0, -0.2, 0.0}, {0.0, 0.0, 0.1}, {0.5, 0.5, -0.3}}) {
      const Pose2D wrong{truth.x + offset.x, truth.y + offset.y, truth.theta + offset.theta};
      EXPECT_GT(at_truth, model.log_likelihood(scan, wrong));
    }
  }
}

TEST(BeamLikelihood, UnusableScansPrepareToNothing) {
  const BeamLikelihood model(single_obstacle_field());
  EXPECT_TRUE(model.prepare(msgs::LaserScan{}).empty());
  msgs::LaserScan scan = fan(10, 2.0F);
  scan.ranges_m.assign(10, kInf);
  EXPECT_TRUE(model.prepare(scan).empty());
  scan = fan(10, 2.0F);
  scan.angle_increment_rad = kNanF;
  EXPECT_TRUE(model.prepare(scan).empty());
  scan = fan(10, 2.0F);
  scan.sensor_in_base.theta = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(model.prepare(scan).empty());
  scan = fan(10, 2.0F);
  scan.range_max_m = 0.0F;
  EXPECT_TRUE(model.prepare(scan).empty());
}

TEST(BeamLikelihood, RefusesBadOptionsAndNoField) {
  EXPECT_THROW(BeamLikelihood(nullptr), std::invalid_argument);
  const auto field = single_obstacle_field();
  BeamLikelihoodOptions options;
  options.max_beams = 1;
  EXPECT_THROW(BeamLikelihood(field, options), std::invalid_argument);
  options = {};
  options.sigma_hit_m = 0.0;
  EXPECT_THROW(BeamLikelihood(field, options), std::invalid_argument);
  options = {};
  options.z_rand = -0.1;
  EXPECT_THROW(BeamLikelihood(field, options), std::invalid_argument);
  options = {};
  options.range_max_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(BeamLikelihood(field, options), std::invalid_argument);
  options = {};
  options.no_return_margin_m = -0.1;
  EXPECT_THROW(BeamLikelihood(field, options), std::invalid_argument);
  options = {};
  options.no_return_weight = 1.5;
  EXPECT_THROW(BeamLikelihood(field, options), std::invalid_argument);
  options = {};
  options.no_return_clearance_rad = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(BeamLikelihood(field, options), std::invalid_argument);
  options = {};
  options.max_no_return_beams = -1;
  EXPECT_THROW(BeamLikelihood(field, options), std::invalid_argument);
}

}  // namespace
}  // namespace mobot::estimation
