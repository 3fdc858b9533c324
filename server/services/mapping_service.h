#pragma once

#include <memory>
#include <mutex>
#include <vector>

#include "api/ports/mapping_port.h"
#include "server/recorder.h"
#include "server/runtime.h"
#include "server/services/map_catalog.h"
#include "server/stages/estimate_stage.h"
#include "server/stages/mapping_stage.h"
#include "server/stages/navigate_stage.h"

namespace mobot::server {

struct MappingStages {
  MappingStage& mapping;
  EstimateStage& estimate;
  NavigateStage& navigate;
};

// The MappingPort (docs/algorithms.md C7): a SLAM session starts from the current estimate, the
// estimate is the SLAM's while it runs, and at the stop the final map is rendered off the loop and
// stored like an imported map (then activated) or dropped.
class MappingService final : public api::MappingPort {
 public:
  MappingService(Runtime& runtime, Recorder& recorder, MapCatalog& catalog, MappingStages stages);
  ~MappingService() override;

  api::MappingStatus mapping_status() const override;
  void start_mapping(api::Completion<api::MappingStatus> done) override;
  void stop_mapping(std::optional<std::string> save_as,
                    api::Completion<api::MappingStopped> done) override;

 private:
  void store(std::string name, mapping::OccupancyGrid grid,
             api::Completion<api::MappingStopped> done);

  Runtime& runtime_;
  Recorder& recorder_;
  MapCatalog& catalog_;
  MappingStages stages_;
  // Sessions that ended: a worker finishes on its own thread and must not be destroyed there.
  std::mutex retired_mutex_;
  std::vector<std::shared_ptr<SlamWorker>> retired_;
};

}  // namespace mobot::server
