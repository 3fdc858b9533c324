#pragma once

#include "drivers/base_driver.h"

namespace mobot::sim {

class SimBackend;

// The simulated motor base: wheel set-points become the body velocity the Simulator drives (it
// adds its own wheel errors); its encoders and collisions are read back like a real base's.
class SimBase final : public drivers::BaseDriver {
 public:
  explicit SimBase(SimBackend& backend) : backend_(backend) {}

  void set_wheel_command(const msgs::WheelCommand& command) override;
  std::optional<msgs::WheelEncoders> read_encoders(double now_s) override;
  std::vector<msgs::Contact> take_contacts() override;
  drivers::DeviceStatus status() const override { return {}; }

 private:
  SimBackend& backend_;
};

}  // namespace mobot::sim
