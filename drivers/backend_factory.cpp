#include "drivers/backend_factory.h"

#include "drivers/hardware/hardware_backend.h"
#include "drivers/sim/sim_backend.h"

namespace mobot::drivers {

std::unique_ptr<Backend> make_backend(const BackendOptions& options) {
  if (options.backend == "sim") return sim::make_sim_backend(options);
  if (options.backend == "hardware") return hardware::make_hardware_backend(options);
  throw BackendError("backend: '" + options.backend + "' is not one of sim, hardware");
}

}  // namespace mobot::drivers
