#pragma once

#include <cstdint>
#include <memory>

#include "core/mapping/keepout_zone.h"
#include "core/mapping/occupancy_grid.h"
#include "server/tick_context.h"

namespace mobot::server {

// The map localization and planning use from now on.
struct ActiveMap {
  std::int64_t id = 0;
  std::uint64_t generation = 0;  // counts activations: results computed on an older map are stale
  std::shared_ptr<const mapping::OccupancyGrid> grid;
  // Where planning never goes (polygons in the map frame).
  std::shared_ptr<const std::vector<mapping::KeepoutZone>> zones =
      std::make_shared<const std::vector<mapping::KeepoutZone>>();
};

// Something that works on the active map (a stage, a layer). A new map arrives in two steps:
// prepare() does the heavy part (inflating, extracting lines) off the control loop, one map at a
// time; apply() then swaps it in on the control loop, between ticks, in registration order.
class MapListener {
 public:
  virtual ~MapListener() = default;
  virtual void prepare_map(const ActiveMap& map) = 0;
  virtual void apply_map(const ActiveMap& map, TickContext& context) = 0;
};

}  // namespace mobot::server
