#include "db/run_store.h"

namespace mobot::db {
namespace {

// Goal outcomes are counted from the events, so the run row never disagrees with its events.
constexpr std::string_view kRunSelect = R"sql(
SELECT r.id, r.name, r.started_unix_s, r.ended_unix_s, r.distance_m,
  (SELECT COUNT(*) FROM events e WHERE e.run_id = r.id AND e.kind = 'goal'
     AND json_extract(e.detail, '$.status') = 'succeeded'),
  (SELECT COUNT(*) FROM events e WHERE e.run_id = r.id AND e.kind = 'goal'
     AND json_extract(e.detail, '$.status') = 'failed'),
  (SELECT COUNT(*) FROM events e WHERE e.run_id = r.id AND e.kind = 'goal'
     AND json_extract(e.detail, '$.status') = 'canceled')
FROM runs r
)sql";

RunRecord read_run(const Statement& row) {
  RunRecord run;
  run.id = row.column_int64(0);
  run.name = row.column_text(1);
  run.started_unix_s = row.column_double(2);
  if (!row.column_is_null(3)) run.ended_unix_s = row.column_double(3);
  run.distance_m = row.column_double(4);
  run.goals = {static_cast<int>(row.column_int64(5)), static_cast<int>(row.column_int64(6)),
               static_cast<int>(row.column_int64(7))};
  return run;
}

}  // namespace

std::int64_t RunStore::start_run(const std::string& name, double started_unix_s) {
  return database_.write([&](const Connection& tx) {
    tx.prepare("INSERT INTO runs (name, started_unix_s) VALUES (?, ?)")
        .bind(1, name)
        .bind(2, started_unix_s)
        .run();
    return tx.last_insert_id();
  });
}

void RunStore::append(std::int64_t run_id, const std::vector<TrajectorySample>& samples,
                      const std::vector<EventRecord>& events, double distance_m) {
  database_.write([&](const Connection& tx) {
    Statement sample_insert =
        tx.prepare("INSERT INTO trajectory (run_id, t_s, x, y, theta) VALUES (?, ?, ?, ?, ?)");
    for (const auto& sample : samples) {
      sample_insert.bind(1, run_id)
          .bind(2, sample.t_s)
          .bind(3, sample.x)
          .bind(4, sample.y)
          .bind(5, sample.theta)
          .run();
      sample_insert.reset();
    }
    Statement event_insert =
        tx.prepare("INSERT INTO events (run_id, t_s, kind, detail) VALUES (?, ?, ?, ?)");
    for (const auto& event : events) {
      event_insert.bind(1, run_id)
          .bind(2, event.t_s)
          .bind(3, event.kind)
          .bind(4, event.detail_json.empty() ? std::string_view("{}") : event.detail_json)
          .run();
      event_insert.reset();
    }
    tx.prepare("UPDATE runs SET distance_m = ? WHERE id = ?")
        .bind(1, distance_m)
        .bind(2, run_id)
        .run();
    if (tx.changes() == 0) throw DbError("no run with id " + std::to_string(run_id));
  });
}

void RunStore::end_run(std::int64_t run_id, double ended_unix_s, double distance_m) {
  database_.write([&](const Connection& tx) {
    tx.prepare("UPDATE runs SET ended_unix_s = ?, distance_m = ? WHERE id = ?")
        .bind(1, ended_unix_s)
        .bind(2, distance_m)
        .bind(3, run_id)
        .run();
    if (tx.changes() == 0) throw DbError("no run with id " + std::to_string(run_id));
  });
}

int RunStore::close_dangling_runs(double now_unix_s) {
  return database_.write([&](const Connection& tx) {
    // The last trajectory sample tells how long the run lasted in robot time; with no sample,
    // the run ended when it started. Never later than now.
    tx.prepare(R"sql(
UPDATE runs SET ended_unix_s = MIN(?, started_unix_s + COALESCE(
  (SELECT MAX(t_s) - MIN(t_s) FROM trajectory WHERE run_id = runs.id), 0))
WHERE ended_unix_s IS NULL)sql")
        .bind(1, now_unix_s)
        .run();
    return tx.changes();
  });
}

std::vector<RunRecord> RunStore::list() const {
  return database_.read([](const Connection& connection) {
    Statement rows = connection.prepare(std::string(kRunSelect) + " ORDER BY r.id");
    std::vector<RunRecord> out;
    while (rows.step()) out.push_back(read_run(rows));
    return out;
  });
}

std::optional<RunRecord> RunStore::get(std::int64_t run_id) const {
  return database_.read([run_id](const Connection& connection) -> std::optional<RunRecord> {
    Statement row = connection.prepare(std::string(kRunSelect) + " WHERE r.id = ?");
    row.bind(1, run_id);
    if (!row.step()) return std::nullopt;
    return read_run(row);
  });
}

std::vector<TrajectorySample> RunStore::trajectory(std::int64_t run_id) const {
  return database_.read([run_id](const Connection& connection) {
    Statement rows = connection.prepare(
        "SELECT t_s, x, y, theta FROM trajectory WHERE run_id = ? ORDER BY rowid");
    rows.bind(1, run_id);
    std::vector<TrajectorySample> out;
    while (rows.step()) {
      out.push_back({rows.column_double(0), rows.column_double(1), rows.column_double(2),
                     rows.column_double(3)});
    }
    return out;
  });
}

std::vector<EventRecord> RunStore::events(std::int64_t run_id) const {
  return database_.read([run_id](const Connection& connection) {
    Statement rows =
        connection.prepare("SELECT t_s, kind, detail FROM events WHERE run_id = ? ORDER BY id");
    rows.bind(1, run_id);
    std::vector<EventRecord> out;
    while (rows.step())
      out.push_back({rows.column_double(0), rows.column_text(1), rows.column_text(2)});
    return out;
  });
}

}  // namespace mobot::db
