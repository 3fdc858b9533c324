#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "api/ports/result.h"

namespace mobot::api {

struct MappingStatus {
  bool mapping = false;
  std::int64_t scans = 0;  // scans the SLAM has taken since the start
  std::int64_t nodes = 0;  // of which kept as pose-graph nodes
  std::int64_t loop_closures = 0;
  std::optional<double> started_t;  // robot clock
};

struct MappingStopped {
  std::optional<std::int64_t> map_id;  // the stored map, nothing when discarded
};

// Building a map of a new place (SLAM) while the operator drives. Thread-safe.
class MappingPort {
 public:
  virtual ~MappingPort() = default;

  virtual MappingStatus mapping_status() const = 0;
  // SLAM starts from the robot's pose estimate now. kConflict mapping_active, estop_engaged.
  virtual void start_mapping(Completion<MappingStatus> done) = 0;
  // Stops; with a name the map is stored like an imported one and made active, without one it is
  // discarded. kConflict not_mapping.
  virtual void stop_mapping(std::optional<std::string> save_as,
                            Completion<MappingStopped> done) = 0;
};

}  // namespace mobot::api
