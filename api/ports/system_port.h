#pragma once

#include <string>

namespace mobot::api {

// What the server says about itself. Thread-safe and never waits.
class SystemPort {
 public:
  virtual ~SystemPort() = default;

  virtual std::string backend_name() const = 0;
  virtual double uptime_s() const = 0;
  // The robot side's Prometheus metrics (control loop, stages, sensors, recorder), text format.
  virtual std::string metrics_text() const = 0;
};

}  // namespace mobot::api
