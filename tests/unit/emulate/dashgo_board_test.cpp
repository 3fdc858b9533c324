// The Dashgo's base driver against the emulated Arduino on a pseudo-terminal: the real serial
// code, the real protocol, and each fault the line can have.
#include "drivers/hardware/dashgo_board.h"

#include <gtest/gtest.h>

#include "tests/unit/emulate/line_harness.h"
#include "tools/emulate/devices/dashgo_base_device.h"

namespace mobot::emulate {
namespace {

using testing::eventually;

class DashgoBoardTest : public ::testing::Test {
 protected:
  DashgoBoardTest() {
    auto device = std::make_unique<DashgoBaseDevice>(
        DashgoBaseDeviceOptions{.sonars_in_base = {{0.2, 0.0, 0.0}}}, world_);
    model_ = device.get();
    harness_ = std::make_unique<testing::LineHarness>(std::move(device));
    drivers::hardware::DashgoBoardOptions options;
    options.serial.device = harness_->path().string();
    options.sonars_in_base = {{0.2, 0.0, 0.0}};
    options.boot_timeout_s = 1.0;
    board_ = std::make_unique<drivers::hardware::DashgoBoard>(options);
  }
  ~DashgoBoardTest() override {
    board_.reset();
    harness_.reset();
  }

  bool ok() const { return board_->health().status().ok; }
  std::string reason() const { return board_->health().status().reason; }

  testing::EmptyWorld world_;
  DashgoBaseDevice* model_ = nullptr;
  std::unique_ptr<testing::LineHarness> harness_;
  std::unique_ptr<drivers::hardware::DashgoBoard> board_;
};

TEST_F(DashgoBoardTest, DrivesTheWheelsAndReadsTheirCounts) {
  board_->start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 2.0)) << reason();
  // 2 rad/s on a 1200-tick wheel: 382 ticks per second.
  board_->set_wheel_command({2.0, 2.0});
  std::int64_t left = 0;
  ASSERT_TRUE(eventually(
      [&] {
        if (auto counts = board_->take_counts()) left = counts->left_ticks;
        return left > 300;
      },
      2.0));
  EXPECT_GT(world_.base_pose().x, 0.05);
  EXPECT_TRUE(eventually([&] { return board_->take_sonar().has_value(); }, 1.0));
  EXPECT_NEAR(board_->battery_v(), 12.4, 1e-9);
}

TEST_F(DashgoBoardTest, ReadsTheEmergencyButton) {
  board_->start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 2.0));
  harness_->with_line([&](DeviceLine&) { model_->set_estop_button(true); });
  EXPECT_TRUE(eventually([&] { return board_->estop_button_pressed(); }, 1.0));
  harness_->with_line([&](DeviceLine&) { model_->set_estop_button(false); });
  EXPECT_TRUE(eventually([&] { return !board_->estop_button_pressed(); }, 1.0));
}

TEST_F(DashgoBoardTest, AMissingDeviceIsMissingUntilItAppears) {
  harness_->with_line([&](DeviceLine& line) { line.set_fault(LineFault::kUnplug, 0.0, 0.0); });
  board_->start();
  EXPECT_TRUE(eventually([&] { return reason() == "missing"; }, 1.0)) << reason();
  harness_->with_line([&](DeviceLine& line) { line.clear_fault(); });
  EXPECT_TRUE(eventually([&] { return ok(); }, 4.0)) << reason();
}

TEST_F(DashgoBoardTest, EachLineFaultIsReportedAndRecoveredFrom) {
  board_->start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 2.0));
  const std::vector<std::pair<LineFault, std::string>> faults{
      {LineFault::kUnplug, "missing"},   {LineFault::kDrop, "silent"},
      {LineFault::kStall, "silent"},     {LineFault::kGarbage, "silent"},
      {LineFault::kChecksum, "garbage"},
  };
  for (const auto& [fault, expected] : faults) {
    harness_->with_line([&](DeviceLine& line) { line.set_fault(fault, harness_->seconds(), 0); });
    // Noise on the line may read as no reply (non-printable bytes spoil the line) or as a
    // reply that does not parse: either way the board is not ok.
    EXPECT_TRUE(eventually([&] { return !ok(); }, 1.0)) << expected;
    if (fault != LineFault::kGarbage) {
      EXPECT_EQ(reason(), expected);
    }
    harness_->with_line([&](DeviceLine& line) { line.clear_fault(); });
    EXPECT_TRUE(eventually([&] { return ok(); }, 4.0)) << expected << ": " << reason();
  }
  EXPECT_GE(board_->health().reconnects(), 5U);
}

TEST_F(DashgoBoardTest, FiftyUnplugsLeakNoFileDescriptor) {
  board_->start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 2.0));
  const int before = testing::open_fd_count();
  for (int i = 0; i < 50; ++i) {
    harness_->with_line([&](DeviceLine& line) { line.set_fault(LineFault::kUnplug, 0.0, 0.0); });
    ASSERT_TRUE(eventually([&] { return !ok(); }, 1.0));
    harness_->with_line([&](DeviceLine& line) { line.clear_fault(); });
    ASSERT_TRUE(eventually([&] { return ok(); }, 4.0)) << i << ": " << reason();
  }
  EXPECT_EQ(testing::open_fd_count(), before);
}

}  // namespace
}  // namespace mobot::emulate
