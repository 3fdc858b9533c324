#pragma once

#include <functional>
#include <string>

#include "core/timing/rate_schedule.h"
#include "drivers/sensor_driver.h"

namespace mobot::sim {

// A simulated sensor that is read at its nominal rate: on each due poll it asks the Simulator
// (through `read`) for a reading and stamps it with the robot clock, as a driver stamps a real
// device's reading when it arrives.
template <class Msg>
class SimSensor final : public drivers::SensorDriver<Msg> {
 public:
  SimSensor(std::string name, double rate_hz, std::function<Msg()> read)
      : name_(std::move(name)),
        rate_hz_(rate_hz),
        schedule_(1.0 / rate_hz),
        read_(std::move(read)) {}

  std::string_view name() const override { return name_; }
  double nominal_rate_hz() const override { return rate_hz_; }
  std::optional<Msg> poll(double now_s) override {
    if (!schedule_.due(now_s)) return std::nullopt;
    schedule_.taken(now_s);
    Msg reading = read_();
    reading.stamp_s = now_s;
    return reading;
  }
  drivers::DeviceStatus status() const override { return {}; }

 private:
  std::string name_;
  double rate_hz_;
  timing::RateSchedule schedule_;
  std::function<Msg()> read_;
};

}  // namespace mobot::sim
