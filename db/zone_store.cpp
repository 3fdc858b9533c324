#include "db/zone_store.h"

#include <bit>
#include <cstring>

namespace mobot::db {
namespace {

static_assert(std::endian::native == std::endian::little,
              "zone polygons are stored as little-endian float64");

std::vector<std::uint8_t> encode_polygon(const std::vector<geometry::Point2D>& polygon) {
  std::vector<std::uint8_t> bytes(polygon.size() * 2 * sizeof(double));
  std::size_t offset = 0;
  for (const auto& point : polygon) {
    std::memcpy(bytes.data() + offset, &point.x, sizeof(double));
    std::memcpy(bytes.data() + offset + sizeof(double), &point.y, sizeof(double));
    offset += 2 * sizeof(double);
  }
  return bytes;
}

std::vector<geometry::Point2D> decode_polygon(const std::vector<std::uint8_t>& bytes,
                                              std::int64_t zone_id) {
  constexpr std::size_t kVertexBytes = 2 * sizeof(double);
  if (bytes.size() % kVertexBytes != 0) {
    throw DbError("zone " + std::to_string(zone_id) + " is corrupt: " +
                  std::to_string(bytes.size()) + " polygon bytes");
  }
  std::vector<geometry::Point2D> polygon(bytes.size() / kVertexBytes);
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    std::memcpy(&polygon[i].x, bytes.data() + i * kVertexBytes, sizeof(double));
    std::memcpy(&polygon[i].y, bytes.data() + i * kVertexBytes + sizeof(double), sizeof(double));
  }
  return polygon;
}

bool map_exists(const Connection& connection, std::int64_t map_id) {
  Statement row = connection.prepare("SELECT 1 FROM maps WHERE id = ?");
  row.bind(1, map_id);
  return row.step();
}

}  // namespace

std::optional<std::int64_t> ZoneStore::insert(std::int64_t map_id, const std::string& name,
                                              const std::vector<geometry::Point2D>& polygon,
                                              double created_unix_s) {
  return database_.write([&](const Connection& tx) -> std::optional<std::int64_t> {
    if (!map_exists(tx, map_id)) return std::nullopt;
    const std::vector<std::uint8_t> bytes = encode_polygon(polygon);
    tx.prepare("INSERT INTO map_zones (map_id, name, polygon, created_unix_s) VALUES (?, ?, ?, ?)")
        .bind(1, map_id)
        .bind(2, name)
        .bind(3, std::span<const std::uint8_t>(bytes))
        .bind(4, created_unix_s)
        .run();
    return tx.last_insert_id();
  });
}

std::optional<std::vector<mapping::KeepoutZone>> ZoneStore::list(std::int64_t map_id) const {
  return database_.read(
      [map_id](const Connection& connection) -> std::optional<std::vector<mapping::KeepoutZone>> {
        if (!map_exists(connection, map_id)) return std::nullopt;
        Statement rows = connection.prepare(
            "SELECT id, name, polygon FROM map_zones WHERE map_id = ? ORDER BY id");
        rows.bind(1, map_id);
        std::vector<mapping::KeepoutZone> zones;
        while (rows.step()) {
          mapping::KeepoutZone zone;
          zone.id = rows.column_int64(0);
          zone.name = rows.column_text(1);
          zone.polygon = decode_polygon(rows.column_blob(2), zone.id);
          zones.push_back(std::move(zone));
        }
        return zones;
      });
}

ZoneStore::RemoveResult ZoneStore::remove(std::int64_t map_id, std::int64_t zone_id) {
  return database_.write([&](const Connection& tx) {
    if (!map_exists(tx, map_id)) return RemoveResult::kNoMap;
    Statement del = tx.prepare("DELETE FROM map_zones WHERE id = ? AND map_id = ?");
    del.bind(1, zone_id).bind(2, map_id).run();
    return tx.changes() > 0 ? RemoveResult::kRemoved : RemoveResult::kNoZone;
  });
}

}  // namespace mobot::db
