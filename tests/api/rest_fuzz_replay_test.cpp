// The REST fuzz target's corpus (tests/fuzz/rest_bodies_fuzz.cpp) replayed against a real mobotd
// and its SQLite store. The fuzz target checks a million inputs against the unit tests' fakes;
// this checks that what the fakes stood for holds of the real server: every request is answered,
// never with a 5xx, and one that is refused (4xx) leaves the database as it was, byte for byte.
//
// The corpus: tests/fuzz/corpus/fuzz_rest_bodies, and the directories named in
// MOBOT_REST_FUZZ_CORPUS (colon-separated), which deploy/test.sh sets to the corpus its fuzzing
// phase grew.
#include <sqlite3.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <sstream>

#include "rest_fuzz_input.h"
#include "support/api_test.h"

namespace mobot::testing {
namespace {

namespace fs = std::filesystem;

// Every table as text, row by row, but for what the robot's own motion writes: its trajectory and
// the distance of the run. What an accepted command set going (a drive, a goal, a sweep) is left
// to finish before the next request is judged.
using DatabaseSnapshot = std::map<std::string, std::string>;

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

DatabaseSnapshot read_database(const fs::path& file) {
  DatabaseSnapshot snapshot;
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(file.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
    snapshot["(open)"] = sqlite3_errmsg(db);
    sqlite3_close(db);
    return snapshot;
  }
  sqlite3_busy_timeout(db, 5000);
  // One read transaction: the tables as of one moment.
  sqlite3_exec(db, "BEGIN", nullptr, nullptr, nullptr);
  for (const auto& [table, query] : kSnapshotQueries)
    snapshot[std::string(table)] = table_text(db, query);
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

std::vector<fs::path> corpus_files() {
  std::vector<fs::path> directories{fs::path(MOBOT_SOURCE_ROOT) /
                                    "tests/fuzz/corpus/fuzz_rest_bodies"};
  if (const char* extra = std::getenv("MOBOT_REST_FUZZ_CORPUS")) {
    std::stringstream list(extra);
    for (std::string directory; std::getline(list, directory, ':');) {
      if (!directory.empty()) directories.emplace_back(directory);
    }
  }
  std::vector<fs::path> files;
  for (const fs::path& directory : directories) {
    for (const auto& entry : fs::directory_iterator(directory)) {
      if (entry.is_regular_file()) files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The printable start of a request, for a failure message.
std::string describe(const fuzz::RestFuzzRecord& record) {
  std::string text = std::string(record.method()) + " " +
                     std::string(record.target.substr(0, 120)) + " as '" +
                     std::string(record.credential().name) + "' body: ";
  for (const char c : record.body.substr(0, 200)) {
    text += (c >= 0x20 && c < 0x7F) ? c : '.';
  }
  return text;
}

class RestFuzzReplay : public ServerSuite<RestFuzzReplay> {
 protected:
  static void SetUpTestSuite() {
    ServerSuite<RestFuzzReplay>::SetUpTestSuite();
    operator2_token_ = create_token(admin(), "operator", "second operator");
  }

  static fs::path database() { return server().data_dir() / "mobot.sqlite"; }

  // The fuzz target's credential names, made the suite's real tokens.
  static std::string authorization(const fuzz::RestFuzzCredential& credential) {
    const std::map<std::string_view, std::string> tokens{{"viewer", viewer_token()},
                                                         {"operator", operator_token()},
                                                         {"admin", server().token()},
                                                         {"operator2", operator2_token_}};
    const auto token = tokens.find(credential.name);
    return std::string(credential.scheme) +
           (token != tokens.end() ? token->second : std::string(credential.name));
  }

  // Waits until what an accepted command set going has finished writing: the store reads the same
  // twice, 200 ms apart.
  static DatabaseSnapshot settled_database() {
    DatabaseSnapshot last = read_database(database());
    const auto deadline = std::chrono::steady_clock::now() + 60s;
    while (std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(200ms);
      DatabaseSnapshot now = read_database(database());
      if (now == last) return now;
      last = std::move(now);
    }
    ADD_FAILURE() << "the store is still changing after 60 s";
    return last;
  }

  static inline std::string operator2_token_;
};

TEST_F(RestFuzzReplay, NoRequestOfTheCorpusGetsA5xxAndNoRefusedOneChangesTheDatabase) {
  const std::vector<fs::path> files = corpus_files();
  ASSERT_FALSE(files.empty());
  std::map<int, int> replies_by_status;
  int requests = 0;
  DatabaseSnapshot before = settled_database();
  for (const fs::path& file : files) {
    const std::string input = read_bytes(file);
    for (const fuzz::RestFuzzRecord& record : fuzz::rest_fuzz_records(input)) {
      if (!record.target_reaches_router()) continue;
      ++requests;
      const HttpReply reply = anonymous().request_with_authorization(
          std::string(record.method()), std::string(record.target), std::string(record.body),
          record.credential().empty() ? std::string{} : authorization(record.credential()));
      ++replies_by_status[reply.status];
      ASSERT_TRUE(server().alive()) << file.filename() << ": " << describe(record);
      ASSERT_GT(reply.status, 0) << file.filename() << ": " << reply.body << "\n"
                                 << describe(record);
      ASSERT_LT(reply.status, 500) << file.filename() << ": " << reply.body << "\n"
                                   << describe(record);
      if (reply.status >= 400) {
        const DatabaseSnapshot after = read_database(database());
        ASSERT_EQ(changed_tables(before, after), "")
            << file.filename() << ": a refused request (" << reply.status << " " << reply.body
            << ") changed the store\n"
            << describe(record);
      } else {
        before = settled_database();
      }
    }
  }
  std::string statuses;
  for (const auto& [status, count] : replies_by_status) {
    statuses += " " + std::to_string(status) + ":" + std::to_string(count);
  }
  std::cout << "replayed " << files.size() << " inputs, " << requests
            << " requests; replies by status:" << statuses << "\n";
  EXPECT_EQ(viewer().get("/api/v1/robot").status, 200);
}

}  // namespace
}  // namespace mobot::testing
