#pragma once

#include <optional>
#include <vector>

#include "core/msgs/contact.h"
#include "core/msgs/wheel_command.h"
#include "core/msgs/wheel_encoders.h"
#include "drivers/device_status.h"

namespace mobot::drivers {

// The motor base: wheel set-points in, encoder counts out. Called on the control loop each tick.
class BaseDriver {
 public:
  virtual ~BaseDriver() = default;

  // Holds until the next command; a zero command stops the wheels.
  virtual void set_wheel_command(const msgs::WheelCommand& command) = 0;
  // The cumulative counts read this tick, stamped `now_s`; nothing when the base did not answer.
  virtual std::optional<msgs::WheelEncoders> read_encoders(double now_s) = 0;
  // What the base ran into since the last call (bumpers, stalls), oldest first.
  virtual std::vector<msgs::Contact> take_contacts() = 0;
  // Whether the base's own emergency button is pressed; a base without one never is.
  virtual bool estop_button_pressed() const { return false; }
  virtual DeviceStatus status() const = 0;
};

}  // namespace mobot::drivers
