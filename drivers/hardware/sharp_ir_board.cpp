#include "drivers/hardware/sharp_ir_board.h"

#include "drivers/protocol/ros_arduino_bridge.h"

#include "drivers/serial/cycle_pacer.h"

namespace mobot::drivers::hardware {

namespace bridge = protocol::arduino_bridge;

SharpIrBoard::SharpIrBoard(SharpIrBoardOptions options)
    : options_(std::move(options)), curve_(options_.curve) {
  thread_ = std::make_unique<serial::DeviceThread>(
      options_.serial, health_,
      [this](serial::SerialPort& port, const std::stop_token& stop) { session(port, stop); });
}

SharpIrBoard::~SharpIrBoard() { stop(); }

void SharpIrBoard::start() { thread_->start(); }
void SharpIrBoard::stop() { thread_->stop(); }

std::optional<msgs::IrRing> SharpIrBoard::take_ring() {
  const std::lock_guard lock(mutex_);
  return std::exchange(ring_, std::nullopt);
}

std::optional<msgs::IrRing> SharpIrBoard::read_ring(ArduinoLink& link) const {
  msgs::IrRing ring;
  for (std::size_t i = 0; i < options_.pins.size(); ++i) {
    const auto count = link.ask_integers(bridge::analog_read_command(options_.pins[i]), 1);
    // A ring with a hole is not a ring: the safety layer would take the gap for open space.
    if (!count) return std::nullopt;
    const long adc = (*count)[0];
    if (adc < 0 || adc > curve_.options().adc_full_scale) return std::nullopt;
    ring.readings.push_back(
        curve_.reading(static_cast<int>(adc), options_.sensors_in_base[i], options_.cone_rad));
  }
  return ring;
}

void SharpIrBoard::session(serial::SerialPort& port, const std::stop_token& stop) {
  ArduinoLink link(port, health_, options_.link);
  link.await_boot(stop, options_.boot_timeout_s);
  serial::CyclePacer pacer(options_.rate_hz);
  while (!stop.stop_requested()) {
    if (std::optional<msgs::IrRing> ring = read_ring(link)) {
      health_.add_frame();
      health_.set_ok();
      const std::lock_guard lock(mutex_);
      ring_ = std::move(ring);
    }
    pacer.wait_next();
  }
}

}  // namespace mobot::drivers::hardware
