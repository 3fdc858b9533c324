// The REST fuzz target's corpus (tests/fuzz/rest_bodies_fuzz.cpp) replayed against a real mobotd
// and its SQLite store. The fuzz target checks a million inputs against the unit tests' fakes;
// this checks that what the fakes stood for holds of the real server: every request is answered,
// never with a 5xx, and one that is refused (4xx) leaves the database as it was, byte for byte,
// as does every read (GET, HEAD, OPTIONS).
//
// The corpus: tests/fuzz/corpus/fuzz_rest_bodies, and the directories named in
// MOBOT_REST_FUZZ_CORPUS (colon-separated), which deploy/test.sh sets to the corpus its fuzzing
// phase grew.
#include <filesystem>
#include <iostream>
#include <map>

#include "rest_fuzz_input.h"
#include "support/api_test.h"
#include "support/database_snapshot.h"
#include "support/fuzz_corpus.h"

namespace mobot::testing {
namespace {

namespace fs = std::filesystem;

std::string describe(const fuzz::RestFuzzRecord& record) {
  return std::string(record.method()) + " " + printable(record.target, 120) + " as '" +
         std::string(record.credential().name) + "' body: " + printable(record.body);
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

  // The run recorder writes its batch every 200 ms: two reads that far apart could both come
  // before the write of an event the control loop had already recorded (a teleop that lapsed
  // by itself). More than two periods apart, the second comes after it.
  static constexpr auto kSettleSpacing = std::chrono::milliseconds(450);

  // Brings to an end what an accepted request set going, so that nothing it does later is
  // taken for the doing of a refused one: a drive, a goal or follow mode is stopped with the
  // e-stop (engaged and released), a running sweep is waited for; then the store is read until it
  // reads the same twice.
  static DatabaseSnapshot quiet_database() {
    const std::string mode = robot_state(viewer()).value("mode", std::string{});
    if (mode != "idle" && mode != "mapping") {
      EXPECT_EQ(admin().post("/api/v1/estop", json{{"engaged", true}}).status, 200);
      EXPECT_EQ(admin().post("/api/v1/estop", json{{"engaged", false}}).status, 200);
    }
    EXPECT_TRUE(wait_until(
        [] {
          const HttpReply sweeps = viewer().get("/api/v1/sweeps");
          if (sweeps.status != 200) return false;
          for (const json& sweep : sweeps.json()) {
            if (sweep.value("status", "") == "running") return false;
          }
          return true;
        },
        60s, 50ms))
        << "a sweep is still running after 60 s";
    return settled_database(database(), kSettleSpacing);
  }

  static inline std::string operator2_token_;
};

TEST_F(RestFuzzReplay, NoRequestOfTheCorpusGetsA5xxAndNoRefusedOneOrReadChangesTheDatabase) {
  const std::vector<fs::path> files =
      fuzz_corpus_files("fuzz_rest_bodies", "MOBOT_REST_FUZZ_CORPUS");
  ASSERT_FALSE(files.empty());
  std::map<int, int> replies_by_status;
  int requests = 0;
  DatabaseSnapshot before = quiet_database();
  for (const fs::path& file : files) {
    const std::string input = file_bytes(file);
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
      // A read changes nothing either, answered or not; only an accepted command may.
      const bool reads =
          record.method() == "GET" || record.method() == "HEAD" || record.method() == "OPTIONS";
      if (reply.status >= 400 || reads) {
        const DatabaseSnapshot after = read_database(database());
        ASSERT_EQ(changed_tables(before, after), "")
            << file.filename() << ": a " << (reads ? "read" : "refused request") << " ("
            << reply.status << " " << reply.body.substr(0, 200) << ") changed the store\n"
            << describe(record) << "\n"
            << describe_changes(before, after);
      } else {
        before = quiet_database();
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
