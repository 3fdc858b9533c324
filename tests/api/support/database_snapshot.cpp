#include "support/database_snapshot.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <array>
#include <string_view>
#include <thread>
#include <utility>

namespace mobot::testing {
namespace {

constexpr std::array<std::pair<std::string_view, std::string_view>, 6> kSnapshotQueries{{
    {"maps", "SELECT * FROM maps ORDER BY id"},
    {"map_zones", "SELECT * FROM map_zones ORDER BY id"},
    {"tokens", "SELECT * FROM tokens ORDER BY id"},
    {"sweeps", "SELECT * FROM sweeps ORDER BY id"},
    {"events", "SELECT * FROM events ORDER BY id"},
    {"runs", "SELECT id, name, started_unix_s, ended_unix_s FROM runs ORDER BY id"},
}};

std::string table_text(sqlite3* db, std::string_view query) {
  sqlite3_stmt* statement = nullptr;
  if (sqlite3_prepare_v2(db, query.data(), static_cast<int>(query.size()), &statement, nullptr) !=
      SQLITE_OK) {
    return std::string("cannot read: ") + sqlite3_errmsg(db);
  }
  std::string text;
  int step = SQLITE_ROW;
  while ((step = sqlite3_step(statement)) == SQLITE_ROW) {
    for (int column = 0; column < sqlite3_column_count(statement); ++column) {
      // The type, then the value's bytes with their length: no two rows read alike.
      text += std::to_string(sqlite3_column_type(statement, column)) + ":";
      const auto* bytes = static_cast<const char*>(sqlite3_column_blob(statement, column));
      const int size = sqlite3_column_bytes(statement, column);
      text += std::to_string(size) + ":";
      if (bytes != nullptr) text.append(bytes, static_cast<std::size_t>(size));
      text += '|';
    }
    text += '\n';
  }
  if (step != SQLITE_DONE) text += std::string("read failed: ") + sqlite3_errmsg(db);
  sqlite3_finalize(statement);
  return text;
}

}  // namespace

DatabaseSnapshot read_database(const std::filesystem::path& file) {
  DatabaseSnapshot snapshot;
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(file.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
    snapshot["(open)"] = sqlite3_errmsg(db);
    sqlite3_close(db);
    return snapshot;
  }
  sqlite3_busy_timeout(db, 5000);
  sqlite3_exec(db, "BEGIN", nullptr, nullptr, nullptr);
  for (const auto& [table, query] : kSnapshotQueries) {
    snapshot[std::string(table)] = table_text(db, query);
  }
  sqlite3_exec(db, "COMMIT", nullptr, nullptr, nullptr);
  sqlite3_close(db);
  return snapshot;
}

std::string changed_tables(const DatabaseSnapshot& before, const DatabaseSnapshot& after) {
  std::string names;
  for (const auto& [table, text] : after) {
    const auto was = before.find(table);
    if (was == before.end() || was->second != text) names += (names.empty() ? "" : ", ") + table;
  }
  return names;
}

std::string describe_changes(const DatabaseSnapshot& before, const DatabaseSnapshot& after) {
  std::string out;
  for (const auto& [table, text] : after) {
    const auto was = before.find(table);
    const std::string old_text = was == before.end() ? std::string{} : was->second;
    if (old_text == text) continue;
    std::size_t at = 0;
    while (at < text.size() && at < old_text.size() && text[at] == old_text[at]) ++at;
    const std::size_t newline_before = text.rfind('\n', at);
    const std::size_t row_start = newline_before == std::string::npos ? 0 : newline_before + 1;
    const std::size_t row_end = text.find('\n', at);
    std::string row = text.substr(
        row_start, row_end == std::string::npos ? std::string::npos : row_end - row_start);
    for (char& c : row) c = (c >= 0x20 && c < 0x7F) ? c : '.';
    out += table + ": " + row.substr(0, 400) + "\n";
  }
  return out;
}

DatabaseSnapshot settled_database(const std::filesystem::path& file,
                                  std::chrono::milliseconds spacing,
                                  std::chrono::milliseconds timeout) {
  DatabaseSnapshot last = read_database(file);
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(spacing);
    DatabaseSnapshot now = read_database(file);
    if (now == last) return now;
    last = std::move(now);
  }
  ADD_FAILURE() << "the store " << file << " is still changing after " << timeout.count() << " ms";
  return last;
}

}  // namespace mobot::testing
