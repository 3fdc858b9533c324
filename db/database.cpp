#include "db/database.h"

#include <sqlite3.h>

#include <string>

#include "db/migrations.h"

namespace mobot::db {

void Connection::exec(std::string_view sql) const {
  const std::string text(sql);
  char* message = nullptr;
  if (sqlite3_exec(db_, text.c_str(), nullptr, nullptr, &message) != SQLITE_OK) {
    std::string error = message != nullptr ? message : sqlite3_errmsg(db_);
    sqlite3_free(message);
    throw DbError(error);
  }
}

std::int64_t Connection::last_insert_id() const { return sqlite3_last_insert_rowid(db_); }

int Connection::changes() const { return sqlite3_changes(db_); }

void Database::Closer::operator()(sqlite3* db) const { sqlite3_close_v2(db); }

Database::Database(sqlite3* db) : db_(db) {}

Database Database::open(const std::filesystem::path& file) {
  sqlite3* raw = nullptr;
  const int code =
      sqlite3_open_v2(file.c_str(), &raw,
                      SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX, nullptr);
  Database database(raw);
  if (code != SQLITE_OK) {
    throw DbError("cannot open " + file.string() + ": " +
                  (raw != nullptr ? sqlite3_errmsg(raw) : "out of memory"));
  }
  database.configure(true);
  return database;
}

Database Database::open_in_memory() {
  sqlite3* raw = nullptr;
  const int code = sqlite3_open_v2(
      ":memory:", &raw, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX, nullptr);
  Database database(raw);
  if (code != SQLITE_OK) throw DbError("cannot open an in-memory database");
  database.configure(false);
  return database;
}

void Database::configure(bool on_disk) {
  const Connection connection(db_.get());
  // Another process (a backup, the sqlite3 shell) may hold the lock for a moment.
  sqlite3_busy_timeout(db_.get(), 5000);
  if (on_disk) {
    connection.exec("PRAGMA journal_mode = WAL");
    // FULL: a commit is on disk when write() returns, so an acknowledged request survives even a
    // power cut, not only a killed process. Commits are batched, so the fsyncs are few.
    connection.exec("PRAGMA synchronous = FULL");
  }
  connection.exec("PRAGMA foreign_keys = ON");

  const auto migrations = schema_migrations();
  const int version = schema_version();
  if (version > static_cast<int>(migrations.size())) {
    throw DbError("the database has schema version " + std::to_string(version) +
                  ", newer than this mobotd knows (" + std::to_string(migrations.size()) + ")");
  }
  for (auto step = static_cast<std::size_t>(version); step < migrations.size(); ++step) {
    write([&](const Connection& tx) {
      tx.exec(migrations[step]);
      tx.exec("PRAGMA user_version = " + std::to_string(step + 1));
    });
  }
}

int Database::schema_version() const {
  return read([](const Connection& connection) {
    Statement statement = connection.prepare("PRAGMA user_version");
    statement.step();
    return static_cast<int>(statement.column_int64(0));
  });
}

}  // namespace mobot::db
