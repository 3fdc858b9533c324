#pragma once

#include <string_view>

#include "server/tick_context.h"

namespace mobot::server {

// One step of the control tick (read drivers, estimate, perceive, navigate, safety, mux, smooth,
// write base, publish). Runs on the control loop; it takes what earlier stages left in the
// context and leaves what later ones need. Must be quick and must never block.
class Stage {
 public:
  virtual ~Stage() = default;
  virtual std::string_view name() const = 0;
  virtual void step(TickContext& context) = 0;
};

}  // namespace mobot::server
