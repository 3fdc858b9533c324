#pragma once

#include "api/ports/localization_port.h"
#include "server/plugins/plugins.h"
#include "server/recorder.h"
#include "server/runtime.h"
#include "server/stages/estimate_stage.h"

namespace mobot::server {

// The LocalizationPort: the estimator switch and global localization, on the control loop.
class LocalizationService final : public api::LocalizationPort {
 public:
  LocalizationService(Runtime& runtime, Recorder& recorder, EstimateStage& estimate,
                      const ConfiguredPlugins& plugins);

  std::vector<std::string> localization_methods() const override;
  void set_localization_method(const std::string& method,
                               api::Completion<std::string> done) override;
  void localize_globally(api::Completion<std::string> done) override;

 private:
  Runtime& runtime_;
  Recorder& recorder_;
  EstimateStage& estimate_;
  const ConfiguredPlugins& plugins_;
};

}  // namespace mobot::server
