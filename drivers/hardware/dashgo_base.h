#pragma once

#include "drivers/base_driver.h"
#include "drivers/hardware/dashgo_board.h"

namespace mobot::drivers::hardware {

// The Dashgo's Arduino as mobot's motor base: set-points go to the board's thread, the counts it
// read come back once each.
class DashgoBase final : public BaseDriver {
 public:
  explicit DashgoBase(DashgoBoard& board) : board_(board) {}

  void set_wheel_command(const msgs::WheelCommand& command) override {
    board_.set_wheel_command(command);
  }
  std::optional<msgs::WheelEncoders> read_encoders(double now_s) override {
    const auto counts = board_.take_counts();
    if (!counts) return std::nullopt;
    return msgs::WheelEncoders{now_s, counts->left_ticks, counts->right_ticks};
  }
  // The Dashgo has no bumper: its sonar rules and the IR ring keep it off things.
  std::vector<msgs::Contact> take_contacts() override { return {}; }
  bool estop_button_pressed() const override { return board_.estop_button_pressed(); }
  DeviceStatus status() const override { return board_.health().status(); }

 private:
  DashgoBoard& board_;
};

}  // namespace mobot::drivers::hardware
