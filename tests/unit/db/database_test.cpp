#include "db/database.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "db/migrations.h"

namespace mobot::db {
namespace {

std::filesystem::path fresh_file(const std::string& name) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("mobot_db_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto file = dir / name;
  std::filesystem::remove(file);
  std::filesystem::remove(file.string() + "-wal");
  std::filesystem::remove(file.string() + "-shm");
  return file;
}

TEST(Database, MigratesANewFileToTheLatestSchema) {
  Database database = Database::open(fresh_file("new.sqlite"));
  EXPECT_EQ(database.schema_version(), static_cast<int>(schema_migrations().size()));
}

TEST(Database, UsesWriteAheadLogging) {
  Database database = Database::open(fresh_file("wal.sqlite"));
  const std::string mode = database.read([](const Connection& connection) {
    Statement row = connection.prepare("PRAGMA journal_mode");
    row.step();
    return row.column_text(0);
  });
  EXPECT_EQ(mode, "wal");
}

TEST(Database, ReopeningKeepsDataAndDoesNotMigrateTwice) {
  const auto file = fresh_file("reopen.sqlite");
  {
    Database database = Database::open(file);
    database.write([](const Connection& tx) {
      tx.exec("INSERT INTO runs (name, started_unix_s) VALUES ('a', 1)");
    });
  }
  Database database = Database::open(file);
  const auto count = database.read([](const Connection& connection) {
    Statement row = connection.prepare("SELECT COUNT(*) FROM runs");
    row.step();
    return row.column_int64(0);
  });
  EXPECT_EQ(count, 1);
}

TEST(Database, AFailedUnitOfWorkChangesNothing) {
  Database database = Database::open_in_memory();
  EXPECT_THROW(database.write([](const Connection& tx) {
    tx.exec("INSERT INTO runs (name, started_unix_s) VALUES ('a', 1)");
    tx.exec("INSERT INTO no_such_table VALUES (1)");
  }),
               DbError);
  const auto count = database.read([](const Connection& connection) {
    Statement row = connection.prepare("SELECT COUNT(*) FROM runs");
    row.step();
    return row.column_int64(0);
  });
  EXPECT_EQ(count, 0);
}

TEST(Database, RefusesASchemaNewerThanItKnows) {
  const auto file = fresh_file("future.sqlite");
  {
    Database database = Database::open(file);
    database.write([](const Connection& tx) { tx.exec("PRAGMA user_version = 999"); });
  }
  EXPECT_THROW(Database::open(file), DbError);
}

TEST(Database, OpeningADirectoryFailsWithAClearError) {
  const auto dir = fresh_file("a_directory");
  std::filesystem::create_directories(dir);
  try {
    Database::open(dir);
    FAIL() << "opening a directory must throw";
  } catch (const DbError& error) {
    EXPECT_NE(std::string(error.what()).find("a_directory"), std::string::npos);
  }
}

}  // namespace
}  // namespace mobot::db
