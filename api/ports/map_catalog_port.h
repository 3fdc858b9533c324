#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "api/ports/result.h"
#include "core/geometry/pose2d.h"
#include "core/mapping/keepout_zone.h"
#include "core/mapping/occupancy_grid.h"

namespace mobot::api {

struct MapInfo {
  std::int64_t id = 0;
  std::string name;
  int width = 0;
  int height = 0;
  double resolution_m = 0.0;
  geometry::Pose2D origin;
  double created_unix_s = 0.0;
  bool active = false;
};

// The stored maps and which one the robot uses. Thread-safe.
class MapCatalogPort {
 public:
  virtual ~MapCatalogPort() = default;

  virtual std::vector<MapInfo> list_maps() const = 0;
  virtual std::optional<MapInfo> map_info(std::int64_t id) const = 0;
  virtual std::optional<mapping::OccupancyGrid> map_grid(std::int64_t id) const = 0;
  virtual std::int64_t import_map(const std::string& name, const mapping::OccupancyGrid& grid) = 0;
  // Completes once localization and planning use the map (kNotFound unknown_map).
  virtual void activate_map(std::int64_t id, Completion<MapInfo> done) = 0;
  // Throws DomainException kNotFound unknown_map, kConflict map_active.
  virtual void delete_map(std::int64_t id) = 0;

  // Keep-out zones (planning never enters them). Nothing: no such map.
  virtual std::optional<std::vector<mapping::KeepoutZone>> list_zones(
      std::int64_t map_id) const = 0;
  // The new zone's id once planning on that map avoids it. kNotFound unknown_map, kInvalid
  // invalid_polygon (not a simple polygon).
  virtual void add_zone(std::int64_t map_id, const std::string& name,
                        const std::vector<geometry::Point2D>& polygon,
                        Completion<std::int64_t> done) = 0;
  // kNotFound unknown_map, unknown_zone.
  virtual void delete_zone(std::int64_t map_id, std::int64_t zone_id, Completion<Done> done) = 0;
};

}  // namespace mobot::api
