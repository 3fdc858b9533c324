#pragma once

#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "drivers/base_driver.h"
#include "drivers/sensor_driver.h"

namespace mobot::server::testing {

// A base that records the wheel commands it is given and reports what the test queues.
class FakeBase final : public drivers::BaseDriver {
 public:
  void set_wheel_command(const msgs::WheelCommand& command) override {
    commands.push_back(command);
  }
  std::optional<msgs::WheelEncoders> read_encoders(double now_s) override {
    if (silent) return std::nullopt;
    encoders.stamp_s = now_s;
    return encoders;
  }
  std::vector<msgs::Contact> take_contacts() override {
    std::vector<msgs::Contact> out;
    out.swap(contacts);
    return out;
  }
  drivers::DeviceStatus status() const override { return device_status; }

  std::vector<msgs::WheelCommand> commands;
  msgs::WheelEncoders encoders;
  std::vector<msgs::Contact> contacts;
  drivers::DeviceStatus device_status;
  bool silent = false;
};

// A sensor that yields a reading every poll until the test makes it silent, or a fault.
template <class Msg>
class FakeSensor final : public drivers::SensorDriver<Msg> {
 public:
  FakeSensor(std::string name, Msg reading)
      : name_(std::move(name)), reading_(std::move(reading)) {}

  std::string_view name() const override { return name_; }
  double nominal_rate_hz() const override { return 50.0; }
  std::optional<Msg> poll(double now_s) override {
    if (silent) return std::nullopt;
    Msg reading = reading_;
    reading.stamp_s = now_s;
    return reading;
  }
  drivers::DeviceStatus status() const override { return device_status; }

  bool silent = false;
  drivers::DeviceStatus device_status;

 private:
  std::string name_;
  Msg reading_;
};

}  // namespace mobot::server::testing
