#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/mapping/keepout_zone.h"
#include "db/database.h"

namespace mobot::db {

// The keep-out zones of the stored maps; a map's zones are deleted with it.
class ZoneStore {
 public:
  enum class RemoveResult { kRemoved, kNoMap, kNoZone };

  explicit ZoneStore(Database& database) : database_(database) {}

  // The new zone's id, or nothing (and nothing stored) when the map does not exist.
  std::optional<std::int64_t> insert(std::int64_t map_id, const std::string& name,
                                     const std::vector<geometry::Point2D>& polygon,
                                     double created_unix_s);
  // The map's zones in the order they were made, or nothing when the map does not exist.
  std::optional<std::vector<mapping::KeepoutZone>> list(std::int64_t map_id) const;
  RemoveResult remove(std::int64_t map_id, std::int64_t zone_id);

 private:
  Database& database_;
};

}  // namespace mobot::db
