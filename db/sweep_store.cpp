#include "db/sweep_store.h"

#include <bit>
#include <cstring>

namespace mobot::db {
namespace {

// The cloud is stored as the in-memory floats; the blob's documented layout is little-endian.
static_assert(std::endian::native == std::endian::little);
static_assert(sizeof(perception::CloudPoint) == 4 * sizeof(float));

constexpr std::string_view kColumns =
    "id, status, COALESCE(reason, ''), period_s, step_deg, scans, started_t, ended_t, points";

SweepRecord read_record(const Statement& row) {
  SweepRecord record;
  record.id = row.column_int64(0);
  record.status = row.column_text(1);
  record.reason = row.column_text(2);
  record.period_s = row.column_double(3);
  record.step_deg = row.column_double(4);
  record.scans = static_cast<int>(row.column_int64(5));
  record.started_t = row.column_double(6);
  if (!row.column_is_null(7)) record.ended_t = row.column_double(7);
  record.points = row.column_int64(8);
  return record;
}

}  // namespace

std::int64_t SweepStore::insert_running(double period_s, double step_deg, int scans,
                                        double started_t, double created_unix_s,
                                        std::optional<std::int64_t> run_id) {
  return database_.write([&](const Connection& tx) {
    Statement insert = tx.prepare(
        "INSERT INTO sweeps (run_id, status, period_s, step_deg, scans, started_t, "
        "created_unix_s) VALUES (?, 'running', ?, ?, ?, ?, ?)");
    if (run_id) insert.bind(1, *run_id);
    insert.bind(2, period_s)
        .bind(3, step_deg)
        .bind(4, scans)
        .bind(5, started_t)
        .bind(6, created_unix_s);
    insert.run();
    return tx.last_insert_id();
  });
}

bool SweepStore::finish(std::int64_t id, double ended_t, const perception::PointCloud& cloud,
                        const mapping::OccupancyGrid& obstacle_map) {
  std::vector<std::uint8_t> bytes(cloud.size() * sizeof(perception::CloudPoint));
  if (!cloud.empty()) std::memcpy(bytes.data(), cloud.data(), bytes.size());
  return database_.write([&](const Connection& tx) {
    tx.prepare(
          "UPDATE sweeps SET status = 'done', ended_t = ?, points = ?, cloud = ?, map_width = ?, "
          "map_height = ?, map_resolution_m = ?, map_origin_x = ?, map_origin_y = ?, "
          "map_cells = ? WHERE id = ? AND status = 'running'")
        .bind(1, ended_t)
        .bind(2, static_cast<std::int64_t>(cloud.size()))
        .bind(3, std::span<const std::uint8_t>(bytes))
        .bind(4, obstacle_map.width())
        .bind(5, obstacle_map.height())
        .bind(6, obstacle_map.resolution_m())
        .bind(7, obstacle_map.origin().x)
        .bind(8, obstacle_map.origin().y)
        .bind(9, std::span<const std::uint8_t>(obstacle_map.cells()))
        .bind(10, id)
        .run();
    return tx.changes() == 1;
  });
}

bool SweepStore::fail(std::int64_t id, double ended_t, const std::string& reason) {
  return database_.write([&](const Connection& tx) {
    tx.prepare(
          "UPDATE sweeps SET status = 'failed', ended_t = ?, reason = ? WHERE id = ? AND status = "
          "'running'")
        .bind(1, ended_t)
        .bind(2, reason)
        .bind(3, id)
        .run();
    return tx.changes() == 1;
  });
}

int SweepStore::fail_interrupted(const std::string& reason) {
  return database_.write([&](const Connection& tx) {
    tx.prepare("UPDATE sweeps SET status = 'failed', reason = ? WHERE status = 'running'")
        .bind(1, reason)
        .run();
    return tx.changes();
  });
}

SweepStore::RemoveResult SweepStore::remove(std::int64_t id) {
  return database_.write([id](const Connection& tx) {
    Statement row = tx.prepare("SELECT status FROM sweeps WHERE id = ?");
    row.bind(1, id);
    if (!row.step()) return RemoveResult::kNotFound;
    if (row.column_text(0) == "running") return RemoveResult::kRunning;
    tx.prepare("DELETE FROM sweeps WHERE id = ?").bind(1, id).run();
    return RemoveResult::kRemoved;
  });
}

std::vector<SweepRecord> SweepStore::list() const {
  return database_.read([](const Connection& connection) {
    Statement rows =
        connection.prepare("SELECT " + std::string(kColumns) + " FROM sweeps ORDER BY id");
    std::vector<SweepRecord> out;
    while (rows.step()) out.push_back(read_record(rows));
    return out;
  });
}

std::optional<SweepRecord> SweepStore::get(std::int64_t id) const {
  return database_.read([id](const Connection& connection) -> std::optional<SweepRecord> {
    Statement row =
        connection.prepare("SELECT " + std::string(kColumns) + " FROM sweeps WHERE id = ?");
    row.bind(1, id);
    if (!row.step()) return std::nullopt;
    return read_record(row);
  });
}

std::optional<perception::PointCloud> SweepStore::cloud(std::int64_t id) const {
  return database_.read([id](
                            const Connection& connection) -> std::optional<perception::PointCloud> {
    Statement row =
        connection.prepare("SELECT points, cloud FROM sweeps WHERE id = ? AND status = 'done'");
    row.bind(1, id);
    if (!row.step()) return std::nullopt;
    const std::vector<std::uint8_t> bytes = row.column_blob(1);
    perception::PointCloud cloud(static_cast<std::size_t>(row.column_int64(0)));
    if (bytes.size() != cloud.size() * sizeof(perception::CloudPoint)) {
      throw DbError("sweep " + std::to_string(id) + " is corrupt: " + std::to_string(bytes.size()) +
                    " cloud bytes for " + std::to_string(cloud.size()) + " points");
    }
    if (!bytes.empty()) std::memcpy(cloud.data(), bytes.data(), bytes.size());
    return cloud;
  });
}

std::optional<mapping::OccupancyGrid> SweepStore::obstacle_map(std::int64_t id) const {
  return database_.read(
      [id](const Connection& connection) -> std::optional<mapping::OccupancyGrid> {
        Statement row = connection.prepare(
            "SELECT map_width, map_height, map_resolution_m, map_origin_x, map_origin_y, map_cells "
            "FROM sweeps WHERE id = ? AND status = 'done'");
        row.bind(1, id);
        if (!row.step()) return std::nullopt;
        mapping::OccupancyGrid grid(static_cast<int>(row.column_int64(0)),
                                    static_cast<int>(row.column_int64(1)), row.column_double(2),
                                    {row.column_double(3), row.column_double(4), 0.0});
        std::vector<std::uint8_t> cells = row.column_blob(5);
        if (cells.size() != grid.cells().size()) {
          throw DbError("sweep " + std::to_string(id) + " has a corrupt obstacle map");
        }
        grid.mutable_cells() = std::move(cells);
        return grid;
      });
}

}  // namespace mobot::db
