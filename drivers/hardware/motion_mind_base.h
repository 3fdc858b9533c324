#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "drivers/base_driver.h"
#include "drivers/hardware/motion_mind_line.h"

namespace mobot::drivers::hardware {

// R1's differential base: a Motion Mind 3 board per wheel on one line. Set-points go to the
// line's thread; the counts it read come back once each, the pair from both boards. A board whose
// positive counts roll its wheel backwards (a mirrored motor) has sign -1: its set-points and
// counts are negated, so mobot sees forward as positive on both wheels.
class MotionMindBase final : public BaseDriver {
 public:
  MotionMindBase(std::shared_ptr<MotionMindLine> line, MotionMindLine::BoardId left,
                 MotionMindLine::BoardId right, int left_sign = 1, int right_sign = 1)
      : line_(std::move(line)),
        left_(left),
        right_(right),
        left_sign_(left_sign),
        right_sign_(right_sign) {}

  void set_wheel_command(const msgs::WheelCommand& command) override {
    line_->set_velocity(left_, left_sign_ * command.left_radps);
    line_->set_velocity(right_, right_sign_ * command.right_radps);
  }
  std::optional<msgs::WheelEncoders> read_encoders(double now_s) override {
    const auto counts = line_->take_counts(left_, right_);
    if (!counts) return std::nullopt;
    return msgs::WheelEncoders{now_s, left_sign_ * (*counts)[0], right_sign_ * (*counts)[1]};
  }
  // The boards have no bumper input; the limit inputs are not wired on the wheels.
  std::vector<msgs::Contact> take_contacts() override { return {}; }
  DeviceStatus status() const override { return line_->health().status(); }

 private:
  std::shared_ptr<MotionMindLine> line_;
  MotionMindLine::BoardId left_;
  MotionMindLine::BoardId right_;
  int left_sign_;
  int right_sign_;
};

}  // namespace mobot::drivers::hardware
