// The stream-message fuzz target's corpus (tests/fuzz/stream_messages_fuzz.cpp) replayed against a
// real mobotd over WebSocket, each input as one text message from an operator and from a viewer.
// The fuzz target checks the parser alone; this checks the whole session: every message is
// answered (or, when it is not UTF-8 or too large, the connection closed with its RFC 6455 code),
// the server stays up, and a message that was not carried out leaves the SQLite store as it was,
// byte for byte. Only an accepted teleop or e-stop may write to it (its audit record, the drive's
// stop); after one, the test closes that connection (which ends a drive), waits for the store to
// settle, and releases an e-stop it engaged, so that the inputs after it meet a robot that can
// still be driven.
//
// The corpus: tests/fuzz/corpus/fuzz_stream_messages, and the directories named in
// MOBOT_STREAM_FUZZ_CORPUS (colon-separated), which deploy/test.sh sets to the corpus its fuzzing
// phase grew.
#include <filesystem>
#include <iostream>
#include <map>
#include <set>

#include "support/api_test.h"
#include "support/database_snapshot.h"
#include "support/fuzz_corpus.h"

namespace mobot::testing {
namespace {

namespace fs = std::filesystem;

// A connection's rate limit lets 200 messages through at once: each input is two (itself and the
// ping that fences its replies), so a fresh connection after 90 inputs is never rate-limited.
constexpr int kInputsPerConnection = 90;

// What the server did with one message.
struct MessageOutcome {
  std::vector<std::string> replies;  // the ops of the replies to it, in order
  int close_code = 0;                // not 0: the server closed the connection with this code
  bool carried_out() const {
    for (const std::string& op : replies) {
      if (op == "teleop" || op == "estop") return true;
    }
    return false;
  }
};

// A teleop or an e-stop is answered once the control loop has carried it out, after the ping
// that follows it: its reply is waited for past the fence.
bool answered_later(std::string_view message) {
  const json parsed = json::parse(message, nullptr, false);
  if (!parsed.is_object() || !parsed.contains("op")) return false;
  return parsed.at("op") == "teleop" || parsed.at("op") == "estop";
}

// One role's connection, renewed before its rate limit or after the server closed it.
class StreamSender {
 public:
  StreamSender(std::uint16_t port, std::string token) : port_(port), token_(std::move(token)) {}

  void close() { client_.reset(); }

  MessageOutcome send(std::string_view message) {
    if (!client_ || !client_->is_open() || sent_ >= kInputsPerConnection) {
      client_.reset();
      client_ = std::make_unique<WsClient>(port_, token_);
      sent_ = 0;
    }
    ++sent_;
    const std::string fence = "replay-fence-" + std::to_string(++fences_);
    client_->send_text(message);
    client_->send(json{{"op", "ping"}, {"id", fence}});
    MessageOutcome outcome;
    bool fenced = false;
    while (auto frame = client_->read(5s)) {
      if (frame->opcode == WsOp::kClose) {
        outcome.close_code = frame->close_code();
        return outcome;
      }
      if (!frame->text()) continue;
      const json reply = frame->json();
      if (!reply.contains("op")) continue;  // a topic frame
      if (reply.at("op") == "pong" && reply.value("id", json()) == fence) {
        fenced = true;
      } else {
        outcome.replies.push_back(reply.at("op").get<std::string>());
      }
      if (fenced && (!answered_later(message) || !outcome.replies.empty())) return outcome;
    }
    outcome.replies.push_back(client_->is_open() ? "(no answer in 5 s)" : "(connection lost)");
    return outcome;
  }

 private:
  std::uint16_t port_;
  std::string token_;
  std::unique_ptr<WsClient> client_;
  int sent_ = 0;
  int fences_ = 0;
};

class StreamFuzzReplay : public ServerSuite<StreamFuzzReplay> {
 protected:
  static fs::path database() { return server().data_dir() / "mobot.sqlite"; }
};

TEST_F(StreamFuzzReplay, EveryMessageIsAnsweredAndNoneThatIsRefusedChangesTheDatabase) {
  const std::vector<fs::path> files =
      fuzz_corpus_files("fuzz_stream_messages", "MOBOT_STREAM_FUZZ_CORPUS");
  ASSERT_FALSE(files.empty());
  StreamSender operator_sender(port(), operator_token());
  StreamSender viewer_sender(port(), viewer_token());
  std::map<std::string, int> outcomes;
  int carried_out = 0;
  DatabaseSnapshot before = settled_database(database());
  for (const fs::path& file : files) {
    const std::string input = file_bytes(file);
    for (StreamSender* sender : {&operator_sender, &viewer_sender}) {
      const MessageOutcome outcome = sender->send(input);
      ASSERT_TRUE(server().alive()) << file.filename() << ": " << printable(input);
      const std::string what = file.filename().string() + ": " + printable(input);
      if (outcome.close_code != 0) {
        // Not UTF-8 (1007) or over the message limit (1009): nothing of it was processed.
        EXPECT_TRUE(outcome.close_code == 1007 || outcome.close_code == 1009)
            << outcome.close_code << " " << what;
        ++outcomes["closed " + std::to_string(outcome.close_code)];
      } else {
        ASSERT_FALSE(outcome.replies.empty()) << "no reply to " << what;
        for (const std::string& op : outcome.replies) {
          ASSERT_EQ(op.front() == '(', false) << op << " " << what;
          ++outcomes[op];
        }
      }
      if (outcome.carried_out()) {
        ++carried_out;
        // A drive ends with its connection (recorded as `stream_closed`) rather than when its
        // lease lapses, up to a second later; an e-stop engaged by an input is released, so that
        // later inputs can still drive.
        sender->close();
        admin().post("/api/v1/estop", json{{"engaged", false}});
        // Over two of the run recorder's 200 ms write periods between the reads that must agree.
        before = settled_database(database(), 450ms);
        continue;
      }
      const DatabaseSnapshot after = read_database(database());
      ASSERT_EQ(changed_tables(before, after), "")
          << "a message that was not carried out changed the store: " << what;
    }
  }
  std::string counts;
  for (const auto& [what, count] : outcomes) counts += " " + what + ":" + std::to_string(count);
  std::cout << "replayed " << files.size() << " inputs as an operator and as a viewer; "
            << carried_out << " carried out; replies:" << counts << "\n";
  EXPECT_EQ(viewer().get("/api/v1/robot").status, 200);
}

}  // namespace
}  // namespace mobot::testing
