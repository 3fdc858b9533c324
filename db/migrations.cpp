#include "db/migrations.h"

#include <array>

namespace mobot::db {
namespace {

constexpr std::string_view kInitialSchema = R"sql(
CREATE TABLE maps (
  id INTEGER PRIMARY KEY,
  name TEXT NOT NULL,
  width INTEGER NOT NULL CHECK (width > 0),
  height INTEGER NOT NULL CHECK (height > 0),
  resolution_m REAL NOT NULL CHECK (resolution_m > 0),
  origin_x REAL NOT NULL,
  origin_y REAL NOT NULL,
  origin_theta REAL NOT NULL,
  cells BLOB NOT NULL,
  created_unix_s REAL NOT NULL,
  active INTEGER NOT NULL DEFAULT 0
);
CREATE UNIQUE INDEX maps_one_active ON maps (active) WHERE active = 1;

CREATE TABLE runs (
  id INTEGER PRIMARY KEY,
  name TEXT NOT NULL,
  started_unix_s REAL NOT NULL,
  ended_unix_s REAL,
  distance_m REAL NOT NULL DEFAULT 0
);

CREATE TABLE trajectory (
  run_id INTEGER NOT NULL REFERENCES runs (id) ON DELETE CASCADE,
  t_s REAL NOT NULL,
  x REAL NOT NULL,
  y REAL NOT NULL,
  theta REAL NOT NULL
);
CREATE INDEX trajectory_by_run ON trajectory (run_id, t_s);

CREATE TABLE events (
  id INTEGER PRIMARY KEY,
  run_id INTEGER NOT NULL REFERENCES runs (id) ON DELETE CASCADE,
  t_s REAL NOT NULL,
  kind TEXT NOT NULL,
  detail TEXT NOT NULL DEFAULT '{}'
);
CREATE INDEX events_by_run ON events (run_id, id);

CREATE TABLE tokens (
  id INTEGER PRIMARY KEY,
  hash TEXT NOT NULL UNIQUE,
  role INTEGER NOT NULL CHECK (role BETWEEN 0 AND 2),
  label TEXT NOT NULL DEFAULT '',
  created_unix_s REAL NOT NULL,
  revoked INTEGER NOT NULL DEFAULT 0
);
)sql";

// 3D sweeps (tilting laser): the cloud as float32 x, y, z, intensity per point (little-endian),
// and the IPaBD obstacle map derived from it as occupancy cells.
constexpr std::string_view kSweeps = R"sql(
CREATE TABLE sweeps (
  id INTEGER PRIMARY KEY,
  run_id INTEGER REFERENCES runs (id) ON DELETE SET NULL,
  status TEXT NOT NULL CHECK (status IN ('running', 'done', 'failed')),
  reason TEXT,
  period_s REAL NOT NULL,
  step_deg REAL NOT NULL,
  scans INTEGER NOT NULL CHECK (scans > 0),
  started_t REAL NOT NULL,
  ended_t REAL,
  created_unix_s REAL NOT NULL,
  points INTEGER NOT NULL DEFAULT 0,
  cloud BLOB,
  map_width INTEGER,
  map_height INTEGER,
  map_resolution_m REAL,
  map_origin_x REAL,
  map_origin_y REAL,
  map_cells BLOB
);
)sql";

// Keep-out zones of a map: the polygon as float64 x, y per vertex (little-endian). They go with
// their map.
constexpr std::string_view kZones = R"sql(
CREATE TABLE map_zones (
  id INTEGER PRIMARY KEY,
  map_id INTEGER NOT NULL REFERENCES maps (id) ON DELETE CASCADE,
  name TEXT NOT NULL,
  polygon BLOB NOT NULL,
  created_unix_s REAL NOT NULL
);
CREATE INDEX map_zones_by_map ON map_zones (map_id);
)sql";

// Tokens that lapse: the unix time (whole seconds) from which a token no longer authenticates;
// NULL for a token that lasts until it is revoked.
constexpr std::string_view kTokenExpiry = R"sql(
ALTER TABLE tokens ADD COLUMN expires_at INTEGER;
)sql";

constexpr std::array<std::string_view, 4> kMigrations{kInitialSchema, kSweeps, kZones,
                                                      kTokenExpiry};

}  // namespace

std::span<const std::string_view> schema_migrations() { return kMigrations; }

}  // namespace mobot::db
