#include "db/map_store.h"

namespace mobot::db {
namespace {

constexpr std::string_view kMetaColumns =
    "id, name, width, height, resolution_m, origin_x, origin_y, origin_theta, created_unix_s, "
    "active";

MapMeta read_meta(const Statement& row) {
  MapMeta meta;
  meta.id = row.column_int64(0);
  meta.name = row.column_text(1);
  meta.width = static_cast<int>(row.column_int64(2));
  meta.height = static_cast<int>(row.column_int64(3));
  meta.resolution_m = row.column_double(4);
  meta.origin = {row.column_double(5), row.column_double(6), row.column_double(7)};
  meta.created_unix_s = row.column_double(8);
  meta.active = row.column_int64(9) != 0;
  return meta;
}

}  // namespace

std::int64_t MapStore::insert(const std::string& name, const mapping::OccupancyGrid& grid,
                              double created_unix_s) {
  return database_.write([&](const Connection& tx) {
    tx.prepare(
          "INSERT INTO maps (name, width, height, resolution_m, origin_x, origin_y, origin_theta, "
          "cells, created_unix_s) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)")
        .bind(1, name)
        .bind(2, grid.width())
        .bind(3, grid.height())
        .bind(4, grid.resolution_m())
        .bind(5, grid.origin().x)
        .bind(6, grid.origin().y)
        .bind(7, grid.origin().theta)
        .bind(8, std::span<const std::uint8_t>(grid.cells()))
        .bind(9, created_unix_s)
        .run();
    return tx.last_insert_id();
  });
}

std::vector<MapMeta> MapStore::list() const {
  return database_.read([](const Connection& connection) {
    Statement rows =
        connection.prepare("SELECT " + std::string(kMetaColumns) + " FROM maps ORDER BY id");
    std::vector<MapMeta> out;
    while (rows.step()) out.push_back(read_meta(rows));
    return out;
  });
}

std::optional<MapMeta> MapStore::meta(std::int64_t id) const {
  return database_.read([id](const Connection& connection) -> std::optional<MapMeta> {
    Statement row =
        connection.prepare("SELECT " + std::string(kMetaColumns) + " FROM maps WHERE id = ?");
    row.bind(1, id);
    if (!row.step()) return std::nullopt;
    return read_meta(row);
  });
}

std::optional<mapping::OccupancyGrid> MapStore::grid(std::int64_t id) const {
  return database_.read([id](
                            const Connection& connection) -> std::optional<mapping::OccupancyGrid> {
    Statement row = connection.prepare(
        "SELECT width, height, resolution_m, origin_x, origin_y, origin_theta, cells FROM maps "
        "WHERE id = ?");
    row.bind(1, id);
    if (!row.step()) return std::nullopt;
    const int width = static_cast<int>(row.column_int64(0));
    const int height = static_cast<int>(row.column_int64(1));
    mapping::OccupancyGrid grid(width, height, row.column_double(2),
                                {row.column_double(3), row.column_double(4), row.column_double(5)});
    std::vector<std::uint8_t> cells = row.column_blob(6);
    if (cells.size() != grid.cells().size()) {
      throw DbError("map " + std::to_string(id) + " is corrupt: " + std::to_string(cells.size()) +
                    " cells stored for " + std::to_string(width) + " x " + std::to_string(height));
    }
    grid.mutable_cells() = std::move(cells);
    return grid;
  });
}

bool MapStore::activate(std::int64_t id) {
  return database_.write([id](const Connection& tx) {
    Statement exists = tx.prepare("SELECT 1 FROM maps WHERE id = ?");
    exists.bind(1, id);
    if (!exists.step()) return false;
    tx.exec("UPDATE maps SET active = 0 WHERE active = 1");
    tx.prepare("UPDATE maps SET active = 1 WHERE id = ?").bind(1, id).run();
    return true;
  });
}

std::optional<std::int64_t> MapStore::active_id() const {
  return database_.read([](const Connection& connection) -> std::optional<std::int64_t> {
    Statement row = connection.prepare("SELECT id FROM maps WHERE active = 1");
    if (!row.step()) return std::nullopt;
    return row.column_int64(0);
  });
}

MapStore::RemoveResult MapStore::remove(std::int64_t id) {
  return database_.write([id](const Connection& tx) {
    Statement row = tx.prepare("SELECT active FROM maps WHERE id = ?");
    row.bind(1, id);
    if (!row.step()) return RemoveResult::kNotFound;
    if (row.column_int64(0) != 0) return RemoveResult::kActive;
    tx.prepare("DELETE FROM maps WHERE id = ?").bind(1, id).run();
    return RemoveResult::kRemoved;
  });
}

}  // namespace mobot::db
