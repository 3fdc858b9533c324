#pragma once

#include "drivers/driver_set.h"
#include "server/stage.h"

namespace mobot::server {

// Polls every device of the driver set once: encoders and contacts of the base, then each sensor
// that has a new reading. A device whose driver reports a fault is listed for the safety stage.
class ReadDriversStage final : public Stage {
 public:
  explicit ReadDriversStage(drivers::DriverSet& drivers) : drivers_(drivers) {}
  std::string_view name() const override { return "read_drivers"; }
  void step(TickContext& context) override;

 private:
  drivers::DriverSet& drivers_;
};

}  // namespace mobot::server
