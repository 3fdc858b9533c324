// The costmap stage: the rolling local costmap from the laser, sonar and IR rings around the
// estimate, a table top only the IR ring sees survives the laser's clearing, and the two costmap
// topics go out at their rates.
#include "server/stages/costmap_stage.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace mobot::server {
namespace {

constexpr double kPeriod = 0.02;

// A 360-beam laser at the base centre: every beam returns at `range_m`, except those within
// 5 degrees of `gap_rad`, which see `gap_range_m`.
msgs::LaserScan scan(double range_m, double gap_rad = 10.0, double gap_range_m = 0.0) {
  msgs::LaserScan out;
  out.angle_min_rad = static_cast<float>(-std::numbers::pi);
  out.angle_increment_rad = static_cast<float>(2.0 * std::numbers::pi / 360.0);
  out.range_min_m = 0.05F;
  out.range_max_m = 8.0F;
  for (int i = 0; i < 360; ++i) {
    const double angle = -std::numbers::pi + i * 2.0 * std::numbers::pi / 360.0;
    const bool in_gap =
        std::abs(geometry::wrap_angle(angle - gap_rad)) < 5.0 * std::numbers::pi / 180;
    out.ranges_m.push_back(static_cast<float>(in_gap ? gap_range_m : range_m));
  }
  return out;
}

// One IR sensor facing ahead, reading `range_m` (0.8: nothing in range).
msgs::IrRing ir_ahead(double range_m) {
  msgs::IrRing ring;
  ring.readings.push_back({{0.15, 0.0, 0.0}, 0.1, 0.10, 0.80, range_m});
  return ring;
}

std::uint8_t cost_at(const planning::PlanningGrid& grid, double x, double y) {
  const auto cell = grid.cell_at({x, y});
  EXPECT_TRUE(cell.has_value()) << x << ", " << y << " is outside the window";
  return cell ? grid.cost(*cell) : 0;
}

class CostmapStageTest : public ::testing::Test {
 protected:
  CostmapStageTest() : stage_(CostmapStageOptions{}, [this] { return global_; }) {
    bus_.costmap.subscribe([this](const CostmapSample& sample) { published_.push_back(sample); });
  }

  void tick(std::optional<msgs::LaserScan> laser, std::optional<msgs::IrRing> ir = std::nullopt) {
    ++ticks_;
    context_.begin(ticks_ * kPeriod, kPeriod);
    context_.pose = pose_;
    context_.scan = std::move(laser);
    context_.ir = std::move(ir);
    stage_.step(context_);
  }

  Bus bus_;
  TickContext context_{bus_};
  std::shared_ptr<const planning::PlanningGrid> global_;
  CostmapStage stage_;
  geometry::Pose2D pose_{5.0, 5.0, 0.0};
  std::vector<CostmapSample> published_;
  int ticks_ = 0;
};

TEST_F(CostmapStageTest, ALaserReturnIsLethalInflatedAndTheBeamsWayIsFree) {
  // Everything far (beyond the 3 x 3 m window) but one obstacle 0.99 m ahead (mid-cell).
  tick(scan(6.0, 0.0, 0.99));
  ASSERT_NE(context_.local_costmap, nullptr);
  const planning::PlanningGrid& local = *context_.local_costmap;
  EXPECT_NEAR(local.width() * local.resolution_m(), 3.0, 0.051);
  EXPECT_EQ(cost_at(local, 5.99, 5.0), planning::PlanningGrid::kLethal);
  // Within the inscribed radius (0.3 m) of it: inscribed; farther: decaying, then free.
  EXPECT_EQ(cost_at(local, 5.79, 5.0), planning::PlanningGrid::kInscribed);
  const std::uint8_t margin = cost_at(local, 5.59, 5.0);
  EXPECT_GT(margin, 0);
  EXPECT_LT(margin, planning::PlanningGrid::kInscribed);
  EXPECT_EQ(cost_at(local, 5.3, 5.0), planning::PlanningGrid::kFree);
  EXPECT_EQ(cost_at(local, 5.0, 6.2), planning::PlanningGrid::kFree) << "cleared by a beam";
}

TEST_F(CostmapStageTest, TheWindowFollowsTheRobot) {
  tick(scan(6.0));
  const geometry::Pose2D before = context_.local_costmap->origin();
  pose_ = {7.0, 5.5, 0.0};
  tick(scan(6.0));
  const geometry::Pose2D after = context_.local_costmap->origin();
  EXPECT_NEAR(after.x - before.x, 2.0, 0.051);
  EXPECT_NEAR(after.y - before.y, 0.5, 0.051);
}

TEST_F(CostmapStageTest, ATableTopOnlyTheIrSeesIsNotClearedByTheLaser) {
  // The IR ring sees the table top 0.3 m ahead of its sensor; the laser's beams pass under it.
  tick(scan(6.0), ir_ahead(0.30));
  const double table_x = 5.0 + 0.15 + 0.30;
  EXPECT_EQ(cost_at(*context_.local_costmap, table_x, 5.0), planning::PlanningGrid::kLethal);
  for (int i = 0; i < 20; ++i) tick(scan(6.0));
  EXPECT_EQ(cost_at(*context_.local_costmap, table_x, 5.0), planning::PlanningGrid::kLethal)
      << "the laser cleared what only the IR ring sees";
  // The IR's own reading of nothing in range clears it.
  tick(std::nullopt, ir_ahead(0.80));
  EXPECT_LT(cost_at(*context_.local_costmap, table_x, 5.0), planning::PlanningGrid::kInscribed);
}

TEST_F(CostmapStageTest, TheLocalCostmapGoesOutAt5HzAndTheGlobalOneEvery2s) {
  global_ = std::make_shared<const planning::PlanningGrid>(10, 10, 0.5, geometry::Pose2D{});
  for (int i = 0; i < 200; ++i) tick(i % 3 == 0 ? std::optional(scan(6.0)) : std::nullopt);  // 4 s
  int local = 0;
  int global = 0;
  for (const CostmapSample& sample : published_) {
    ASSERT_NE(sample.costmap, nullptr);
    (sample.local ? local : global) += 1;
    if (!sample.local) {
      EXPECT_EQ(sample.costmap, global_);
    }
  }
  EXPECT_NEAR(local, 20, 1);
  EXPECT_NEAR(global, 2, 1);
}

TEST_F(CostmapStageTest, NoGlobalCostmapNoGlobalFrame) {
  for (int i = 0; i < 150; ++i) tick(std::nullopt);  // 3 s without a map or a reading
  for (const CostmapSample& sample : published_) EXPECT_TRUE(sample.local);
}

}  // namespace
}  // namespace mobot::server
