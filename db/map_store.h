#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"
#include "db/database.h"

namespace mobot::db {

struct MapMeta {
  std::int64_t id = 0;
  std::string name;
  int width = 0;
  int height = 0;
  double resolution_m = 0.0;
  geometry::Pose2D origin;
  double created_unix_s = 0.0;
  bool active = false;
};

// Stored occupancy grids; at most one is active (the one localization and planning use).
class MapStore {
 public:
  enum class RemoveResult { kRemoved, kNotFound, kActive };

  explicit MapStore(Database& database) : database_(database) {}

  std::int64_t insert(const std::string& name, const mapping::OccupancyGrid& grid,
                      double created_unix_s);
  std::vector<MapMeta> list() const;
  std::optional<MapMeta> meta(std::int64_t id) const;
  std::optional<mapping::OccupancyGrid> grid(std::int64_t id) const;
  // Makes `id` the only active map; false (and nothing changed) when no such map exists.
  bool activate(std::int64_t id);
  std::optional<std::int64_t> active_id() const;
  RemoveResult remove(std::int64_t id);

 private:
  Database& database_;
};

}  // namespace mobot::db
