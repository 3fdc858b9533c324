#include "drivers/backend_factory.h"

#include "drivers/sim/sim_backend.h"

namespace mobot::drivers {

std::unique_ptr<Backend> make_backend(const BackendOptions& options) {
  if (options.backend == "sim") return sim::make_sim_backend(options);
  if (options.backend == "hardware") {
    throw BackendError(
        "backend: 'hardware' needs the robot's drivers, and this build has none for the '" +
        options.profile + "' profile yet; use --backend sim");
  }
  throw BackendError("backend: '" + options.backend + "' is not one of sim, hardware");
}

}  // namespace mobot::drivers
