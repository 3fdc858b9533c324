#include "drivers/hardware/hardware_assembly.h"

namespace mobot::drivers::hardware {

serial::SerialOptions read_serial_options(DeviceReader& entry, unsigned default_baud) {
  serial::SerialOptions options;
  entry.text("device", options.device);
  if (options.device.empty()) {
    throw BackendError(entry.path() + ".device: the device's path is required (a tty or a link)");
  }
  double baud = default_baud;
  entry.number("baud", baud, 1200, 4000000);
  options.baud = static_cast<unsigned>(baud);
  return options;
}

}  // namespace mobot::drivers::hardware
