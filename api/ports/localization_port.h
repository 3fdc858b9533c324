#pragma once

#include <string>
#include <vector>

#include "api/ports/result.h"

namespace mobot::api {

// Choosing how the robot localizes. Thread-safe. (The initial pose is ControlPort's.)
class LocalizationPort {
 public:
  virtual ~LocalizationPort() = default;

  // The methods PUT /localization/method accepts (the estimator registry's names).
  virtual std::vector<std::string> localization_methods() const = 0;
  // Switches live, starting from the current estimate; completes with the new method's name.
  // kConflict mapping_active; kInvalid unknown_method.
  virtual void set_localization_method(const std::string& method, Completion<std::string> done) = 0;
  // Spreads the particle filter's belief over the free space of the active map (switching to the
  // particle filter); completes with the method. kConflict no_map, mapping_active.
  virtual void localize_globally(Completion<std::string> done) = 0;
};

}  // namespace mobot::api
