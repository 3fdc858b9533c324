#pragma once

#include <functional>
#include <optional>
#include <string>

#include "drivers/sensor_driver.h"

namespace mobot::drivers::hardware {

// A sensor whose device thread leaves its newest reading to be taken: poll() takes it, if one
// came since the last poll, and stamps it with the robot clock (the device's own clock is not
// the robot's; a reading is at most one control period old when the loop takes it).
template <class Msg>
class PolledSensor final : public SensorDriver<Msg> {
 public:
  // `subscribe`, when given, passes a listener on to the device thread (set_arrival_listener).
  using Subscribe = std::function<void(std::function<void(const Msg&)>)>;

  PolledSensor(std::string name, double rate_hz, std::function<std::optional<Msg>()> take,
               std::function<DeviceStatus()> status, Subscribe subscribe = nullptr)
      : name_(std::move(name)),
        rate_hz_(rate_hz),
        take_(std::move(take)),
        status_(std::move(status)),
        subscribe_(std::move(subscribe)) {}

  std::string_view name() const override { return name_; }
  double nominal_rate_hz() const override { return rate_hz_; }
  std::optional<Msg> poll(double now_s) override {
    std::optional<Msg> reading = take_();
    if (reading) reading->stamp_s = now_s;
    return reading;
  }
  DeviceStatus status() const override { return status_(); }
  bool set_arrival_listener(std::function<void(const Msg&)> listener) override {
    if (!subscribe_) return false;
    subscribe_(std::move(listener));
    return true;
  }

 private:
  std::string name_;
  double rate_hz_;
  std::function<std::optional<Msg>()> take_;
  std::function<DeviceStatus()> status_;
  Subscribe subscribe_;
};

}  // namespace mobot::drivers::hardware
