#include "drivers/hardware/dashgo_board.h"

#include "drivers/serial/cycle_pacer.h"

namespace mobot::drivers::hardware {

namespace bridge = protocol::arduino_bridge;

DashgoBoard::DashgoBoard(DashgoBoardOptions options) : options_(std::move(options)) {
  thread_ = std::make_unique<serial::DeviceThread>(
      options_.serial, health_,
      [this](serial::SerialPort& port, const std::stop_token& stop) { session(port, stop); });
}

DashgoBoard::~DashgoBoard() { stop(); }

void DashgoBoard::start() { thread_->start(); }
void DashgoBoard::stop() { thread_->stop(); }

void DashgoBoard::set_wheel_command(const msgs::WheelCommand& command) {
  const std::lock_guard lock(mutex_);
  command_ = command;
}

std::optional<DashgoBoard::Counts> DashgoBoard::take_counts() {
  const std::lock_guard lock(mutex_);
  return std::exchange(counts_, std::nullopt);
}

std::optional<msgs::SonarRing> DashgoBoard::take_sonar() {
  const std::lock_guard lock(mutex_);
  return std::exchange(sonar_, std::nullopt);
}

bool DashgoBoard::estop_button_pressed() const {
  const std::lock_guard lock(mutex_);
  return estop_button_;
}

double DashgoBoard::battery_v() const {
  const std::lock_guard lock(mutex_);
  return battery_v_;
}

DeviceCounters DashgoBoard::counters() const {
  DeviceCounters counters = health_.counters();
  const double battery = battery_v();
  if (battery > 0.0) counters.battery_v = battery;
  return counters;
}

void DashgoBoard::boot(ArduinoLink& link, const std::stop_token& stop) {
  link.await_boot(stop, options_.boot_timeout_s);
  if (!link.ask_ok(bridge::update_pid_command(options_.pid)) ||
      !link.ask_ok(bridge::command(bridge::kResetEncoders))) {
    throw serial::DeviceFault("refused");
  }
  left_unwrap_.reset();
  right_unwrap_.reset();
}

void DashgoBoard::session(serial::SerialPort& port, const std::stop_token& stop) {
  ArduinoLink link(port, health_, options_.link);
  boot(link, stop);
  health_.set_ok();
  serial::CyclePacer pacer(options_.poll_rate_hz);
  for (int cycle_index = 0; !stop.stop_requested(); ++cycle_index) {
    cycle(link, cycle_index);
    pacer.wait_next();
  }
  // Leaving (shutdown): the wheels stop now rather than at the firmware's 2 s auto-stop.
  link.ask_ok(bridge::motor_speeds_command(0, 0));
}

void DashgoBoard::cycle(ArduinoLink& link, int cycle_index) {
  msgs::WheelCommand command;
  {
    const std::lock_guard lock(mutex_);
    command = command_;
  }
  link.ask_ok(bridge::motor_speeds_command(
      bridge::ticks_per_frame(command.left_radps, options_.ticks_per_wheel_rev),
      bridge::ticks_per_frame(command.right_radps, options_.ticks_per_wheel_rev)));
  if (const auto counts = link.ask_integers(bridge::command(bridge::kReadEncoders), 2)) {
    const Counts unwrapped{left_unwrap_.update((*counts)[0]), right_unwrap_.update((*counts)[1])};
    health_.add_frame();
    health_.set_ok();
    const std::lock_guard lock(mutex_);
    counts_ = unwrapped;
  }
  if (cycle_index % options_.sonar_every == 0) {
    if (const auto ranges = link.ask_integers(bridge::command(bridge::kReadSonars),
                                              options_.sonars_in_base.size())) {
      const msgs::SonarRing ring = sonar_ring(*ranges);
      const std::lock_guard lock(mutex_);
      sonar_ = ring;
    }
    if (const auto button = link.ask_integers(bridge::command(bridge::kReadEstopButton), 1)) {
      const std::lock_guard lock(mutex_);
      estop_button_ = (*button)[0] != 0;
    }
  }
  if (cycle_index % options_.battery_every == 0) {
    if (const auto battery = link.ask_integers(bridge::command(bridge::kReadBattery), 1)) {
      const std::lock_guard lock(mutex_);
      battery_v_ = static_cast<double>((*battery)[0]) / 10.0;
    }
  }
}

msgs::SonarRing DashgoBoard::sonar_ring(const std::vector<long>& ranges_cm) const {
  msgs::SonarRing ring;
  for (std::size_t i = 0; i < ranges_cm.size(); ++i) {
    msgs::RangeReading reading;
    reading.sensor_in_base = options_.sonars_in_base[i];
    reading.cone_rad = options_.sonar_cone_rad;
    reading.range_min_m = options_.sonar_range_min_m;
    reading.range_max_m = options_.sonar_range_max_m;
    // 0 is the firmware's "no echo"; beyond the rated range an echo is not trusted either.
    const double range_m = static_cast<double>(ranges_cm[i]) / 100.0;
    reading.range_m = ranges_cm[i] <= 0 || range_m > options_.sonar_range_max_m
                          ? options_.sonar_range_max_m
                          : std::max(range_m, options_.sonar_range_min_m);
    ring.readings.push_back(reading);
  }
  return ring;
}

}  // namespace mobot::drivers::hardware
