#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string_view>
#include <type_traits>
#include <utility>

#include "db/statement.h"

namespace mobot::db {

// The connection as a unit of work sees it: prepared statements and plain SQL.
class Connection {
 public:
  explicit Connection(sqlite3* db) : db_(db) {}
  Statement prepare(std::string_view sql) const { return Statement(db_, sql); }
  void exec(std::string_view sql) const;
  std::int64_t last_insert_id() const;
  int changes() const;

 private:
  sqlite3* db_;
};

// The SQLite store (WAL, foreign keys on, schema migrated on open). One connection shared by
// every thread: calls are serialised by a mutex, and each write() is one transaction, so a unit of
// work is all on disk or not at all when the process is killed.
class Database {
 public:
  static Database open(const std::filesystem::path& file);
  static Database open_in_memory();

  Database(Database&&) noexcept = default;
  Database& operator=(Database&&) noexcept = default;
  ~Database() = default;

  // Runs fn(const Connection&) inside BEGIN IMMEDIATE ... COMMIT; rolls back if fn throws.
  template <class Fn>
  auto write(Fn&& fn) {
    std::lock_guard lock(*mutex_);
    Connection connection(db_.get());
    connection.exec("BEGIN IMMEDIATE");
    try {
      if constexpr (std::is_void_v<std::invoke_result_t<Fn&, const Connection&>>) {
        fn(std::as_const(connection));
        connection.exec("COMMIT");
      } else {
        auto result = fn(std::as_const(connection));
        connection.exec("COMMIT");
        return result;
      }
    } catch (...) {
      connection.exec("ROLLBACK");
      throw;
    }
  }

  // Runs fn(const Connection&) for reading; one statement sees one consistent snapshot.
  template <class Fn>
  auto read(Fn&& fn) const {
    std::lock_guard lock(*mutex_);
    const Connection connection(db_.get());
    return fn(connection);
  }

  int schema_version() const;

 private:
  struct Closer {
    void operator()(sqlite3* db) const;
  };
  Database(sqlite3* db);
  void configure(bool on_disk);

  std::unique_ptr<sqlite3, Closer> db_;
  std::unique_ptr<std::mutex> mutex_ = std::make_unique<std::mutex>();
};

}  // namespace mobot::db
