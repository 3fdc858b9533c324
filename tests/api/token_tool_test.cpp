// `mobotd token create|list|revoke` against the store of a running mobotd (docs/api.md, "Tokens"):
// a token made by the tool works over HTTP at once, one revoked by the tool is refused at once,
// the list never shows a secret, and bad arguments change nothing. Token expiry over REST:
// `expires_in_s` checked, listed as `expires_at`, and a token past it refused at once.
#include <sqlite3.h>

#include <algorithm>
#include <ctime>
#include <sstream>

#include "support/api_test.h"
#include "support/command.h"

namespace mobot::testing {
namespace {

class TokenToolTest : public ServerSuite<TokenToolTest> {
 protected:
  static CommandResult token_tool(std::vector<std::string> args) {
    args.insert(args.begin(), "token");
    args.insert(args.end(), {"--data-dir", server().data_dir().string()});
    return run_mobotd(args);
  }
  static std::string trimmed(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    return text;
  }
  static json tokens() {
    const HttpReply reply = admin().get("/api/v1/tokens");
    EXPECT_EQ(reply.status, 200) << reply.body;
    return reply.json();
  }
  static json token_with_id(std::int64_t id) {
    for (const json& token : tokens()) {
      if (token.at("id") == id) return token;
    }
    return nullptr;
  }
  // Sets a token's expiry straight in the store, as if its time had come (the API's shortest
  // lifetime is a minute).
  static void expire_in_store(std::int64_t id, std::int64_t expires_at) {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open((server().data_dir() / "mobot.sqlite").c_str(), &db), SQLITE_OK);
    sqlite3_busy_timeout(db, 5000);
    const std::string sql = "UPDATE tokens SET expires_at = " + std::to_string(expires_at) +
                            " WHERE id = " + std::to_string(id);
    EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(db);
  }
};

TEST_F(TokenToolTest, ATokenMadeByTheToolWorksAtOnceAndIsPrintedAlone) {
  const CommandResult made =
      token_tool({"create", "--label", "dana from the tool", "--role", "operator"});
  ASSERT_EQ(made.exit_code, 0) << made.err;
  const std::string token = trimmed(made.out);
  EXPECT_EQ(token.size(), 64U) << "stdout holds the token and nothing else: '" << made.out << "'";
  EXPECT_EQ(token.find_first_not_of("0123456789abcdef"), std::string::npos) << token;
  const HttpClient dana = admin().with_token(token);
  EXPECT_EQ(dana.get("/api/v1/robot").status, 200);
  EXPECT_EQ(dana.post("/api/v1/estop", json{{"engaged", false}}).status, 200) << "an operator";
  EXPECT_EQ(dana.get("/api/v1/tokens").status, 403) << "not an admin";
  bool listed = false;
  for (const json& entry : tokens()) {
    if (entry.at("label") == "dana from the tool") {
      listed = true;
      EXPECT_EQ(entry.at("role"), "operator");
      EXPECT_TRUE(entry.at("expires_at").is_null());
      EXPECT_FALSE(entry.at("revoked").get<bool>());
    }
  }
  EXPECT_TRUE(listed) << tokens().dump();
}

TEST_F(TokenToolTest, ATokenRevokedByTheToolIsRefusedAtOnce) {
  const CommandResult made = token_tool({"create", "--label", "erin", "--role", "viewer"});
  ASSERT_EQ(made.exit_code, 0) << made.err;
  const HttpClient erin = admin().with_token(trimmed(made.out));
  ASSERT_EQ(erin.get("/api/v1/robot").status, 200);
  std::int64_t id = 0;
  for (const json& entry : tokens()) {
    if (entry.at("label") == "erin") id = entry.at("id").get<std::int64_t>();
  }
  ASSERT_GT(id, 0);
  const CommandResult revoked = token_tool({"revoke", std::to_string(id)});
  EXPECT_EQ(revoked.exit_code, 0) << revoked.err;
  const HttpReply refused = erin.get("/api/v1/robot");
  EXPECT_EQ(refused.status, 401) << "a token revoked by the tool must be refused from then on";
  EXPECT_EQ(refused.error_code(), "unauthorized");
  EXPECT_THROW(WsClient(port(), erin.token()), WsHandshakeError);
  EXPECT_TRUE(token_with_id(id).at("revoked").get<bool>());
  // Again, or an id that never was: refused, non-zero.
  EXPECT_NE(token_tool({"revoke", std::to_string(id)}).exit_code, 0);
  const CommandResult unknown = token_tool({"revoke", "999999"});
  EXPECT_NE(unknown.exit_code, 0);
  EXPECT_NE(unknown.err.find("999999"), std::string::npos) << unknown.err;
}

TEST_F(TokenToolTest, TheListShowsEveryTokenButNeverASecret) {
  const CommandResult made =
      token_tool({"create", "--label", "frank", "--role", "admin", "--expires-in-s", "3600"});
  ASSERT_EQ(made.exit_code, 0) << made.err;
  const std::string secret = trimmed(made.out);
  const CommandResult listed = token_tool({"list"});
  ASSERT_EQ(listed.exit_code, 0) << listed.err;
  EXPECT_EQ(listed.out.find(secret), std::string::npos) << listed.out;
  EXPECT_EQ(listed.out.find(operator_token()), std::string::npos) << listed.out;
  EXPECT_EQ(listed.out.find(viewer_token()), std::string::npos) << listed.out;
  for (const char* column : {"id", "role", "label", "created", "expires", "revoked"}) {
    EXPECT_NE(listed.out.find(column), std::string::npos) << column;
  }
  EXPECT_NE(listed.out.find("frank"), std::string::npos) << listed.out;
  EXPECT_NE(listed.out.find("suite viewer"), std::string::npos) << listed.out;
  EXPECT_NE(listed.out.find("never"), std::string::npos) << "tokens without an expiry";
  // frank's line carries his expiry, an hour from now, as a date.
  std::string frank_line;
  std::istringstream lines(listed.out);
  for (std::string line; std::getline(lines, line);) {
    if (line.find("frank") != std::string::npos) frank_line = line;
  }
  EXPECT_EQ(frank_line.find("never"), std::string::npos) << frank_line;
  const std::time_t in_an_hour = std::time(nullptr) + 3600;
  char year[8];
  std::strftime(year, sizeof year, "%Y-", std::gmtime(&in_an_hour));
  EXPECT_EQ(std::count(frank_line.begin(), frank_line.end(), 'Z'), 2) << frank_line;
  EXPECT_NE(frank_line.find(year), std::string::npos) << frank_line;
}

TEST_F(TokenToolTest, BadArgumentsExitNonZeroAndCreateNothing) {
  const std::size_t before = tokens().size();
  const std::vector<std::vector<std::string>> bad{
      {"create", "--label", "gina", "--role", "root"},
      {"create", "--label", "gina"},
      {"create", "--role", "viewer"},
      {"create", "--label", "", "--role", "viewer"},
      {"create", "--label", std::string(129, 'x'), "--role", "viewer"},
      {"create", "--label", "gina", "--role", "viewer", "--expires-in-s", "59"},
      {"create", "--label", "gina", "--role", "viewer", "--expires-in-s", "31536001"},
      {"create", "--label", "gina", "--role", "viewer", "--expires-in-s", "soon"},
      {"revoke", "abc"},
      {"revoke"},
      {"rename"},
  };
  for (const auto& args : bad) {
    const CommandResult result = token_tool(args);
    std::string shown;
    for (const auto& arg : args) shown += arg.substr(0, 20) + " ";
    EXPECT_NE(result.exit_code, 0) << shown;
    EXPECT_TRUE(result.out.empty() || result.out.find("gina") == std::string::npos) << shown;
  }
  EXPECT_EQ(tokens().size(), before) << "a refused command created a token";
  // With no subcommand at all, `mobotd token` says what it takes.
  EXPECT_NE(run_mobotd({"token"}).exit_code, 0);
  // A data dir no mobotd has used: list and revoke refuse, naming it.
  const auto empty = MobotdProcess::make_temp_dir() / "never-used";
  const CommandResult nothing = run_mobotd({"token", "list", "--data-dir", empty.string()});
  EXPECT_NE(nothing.exit_code, 0);
  EXPECT_NE(nothing.err.find(empty.string()), std::string::npos) << nothing.err;
  std::error_code ignored;
  std::filesystem::remove_all(empty.parent_path(), ignored);
}

TEST_F(TokenToolTest, RestTokensTakeALifetimeAndListTheirExpiry) {
  const auto now = static_cast<double>(std::time(nullptr));
  const HttpReply made = admin().post(
      "/api/v1/tokens", json{{"role", "viewer"}, {"label", "hana"}, {"expires_in_s", 60}});
  ASSERT_EQ(made.status, 201) << made.body;
  const json body = made.json();
  ASSERT_TRUE(body.at("expires_at").is_number_integer()) << made.body;
  EXPECT_NEAR(body.at("expires_at").get<double>(), now + 60, 3);
  EXPECT_EQ(token_with_id(body.at("id").get<std::int64_t>()).at("expires_at"),
            body.at("expires_at"));
  EXPECT_EQ(admin().with_token(body.at("token").get<std::string>()).get("/api/v1/robot").status,
            200);
  const HttpReply lasting = admin().post("/api/v1/tokens", json{{"role", "viewer"}});
  ASSERT_EQ(lasting.status, 201);
  EXPECT_TRUE(lasting.json().at("expires_at").is_null());
  EXPECT_EQ(admin().post("/api/v1/tokens", json{{"role", "viewer"}, {"expires_in_s", nullptr}})
                .json()
                .at("expires_at"),
            nullptr);
}

TEST_F(TokenToolTest, ABadLifetimeIs400AndCreatesNothing) {
  const std::size_t before = tokens().size();
  for (const json& lifetime :
       {json(59), json(31536001), json(0), json(-60), json(60.5), json("60"), json(true),
        json::array({60}), json(1e30)}) {
    const HttpReply reply = admin().post(
        "/api/v1/tokens", json{{"role", "viewer"}, {"label", "ivan"}, {"expires_in_s", lifetime}});
    EXPECT_EQ(reply.status, 400) << lifetime.dump() << ": " << reply.body;
    EXPECT_EQ(reply.error_code(), "invalid_field") << lifetime.dump();
  }
  EXPECT_EQ(admin().post("/api/v1/tokens",
                         json{{"role", "viewer"}, {"expires_in_s", 31536000}}).status,
            201);
  EXPECT_EQ(tokens().size(), before + 1) << "a refused request created a token";
}

TEST_F(TokenToolTest, AnExpiredTokenIsRefusedAtOnceOverRestAndTheStream) {
  const HttpReply made = admin().post(
      "/api/v1/tokens", json{{"role", "operator"}, {"label", "jack"}, {"expires_in_s", 600}});
  ASSERT_EQ(made.status, 201) << made.body;
  const HttpClient jack = admin().with_token(made.json().at("token").get<std::string>());
  const auto id = made.json().at("id").get<std::int64_t>();
  ASSERT_EQ(jack.get("/api/v1/robot").status, 200);
  { WsClient stream(port(), jack.token()); }
  expire_in_store(id, static_cast<std::int64_t>(std::time(nullptr)) - 1);
  const HttpReply refused = jack.get("/api/v1/robot");
  EXPECT_EQ(refused.status, 401) << refused.body;
  EXPECT_EQ(refused.error_code(), "unauthorized");
  try {
    WsClient stream(port(), jack.token());
    ADD_FAILURE() << "an expired token opened a stream";
  } catch (const WsHandshakeError& error) {
    EXPECT_EQ(error.status(), 401);
  }
  // Listed as it is: not revoked, expired.
  const json listed = token_with_id(id);
  EXPECT_FALSE(listed.at("revoked").get<bool>());
  EXPECT_LT(listed.at("expires_at").get<double>(), static_cast<double>(std::time(nullptr)));
}

// How long until `stream` gets a close frame, and its code (0 when none came within 3 s).
std::pair<std::chrono::milliseconds, int> time_to_close(WsClient& stream) {
  const auto start = std::chrono::steady_clock::now();
  while (auto frame = stream.read(3s)) {
    if (frame->opcode == WsOp::kClose) {
      return {std::chrono::duration_cast<std::chrono::milliseconds>(
                  std::chrono::steady_clock::now() - start),
              frame->close_code()};
    }
  }
  return {3s, 0};
}

TEST_F(TokenToolTest, AnOpenStreamClosesWith4401WithinASecondOfItsTokensEnd) {
  // Revoked through REST: at once.
  {
    const std::string token = create_token(admin(), "operator", "kate");
    WsClient stream(port(), token);
    const auto id = [&] {
      for (const json& entry : tokens()) {
        if (entry.at("label") == "kate") return entry.at("id").get<std::int64_t>();
      }
      return std::int64_t{-1};
    }();
    ASSERT_EQ(admin().del("/api/v1/tokens/" + std::to_string(id)).status, 204);
    const auto [after, code] = time_to_close(stream);
    EXPECT_EQ(code, 4401);
    EXPECT_LT(after, 1s);
  }
  // Revoked by the tool, in another process: at the server's next check.
  {
    const CommandResult made = token_tool({"create", "--label", "liam", "--role", "viewer"});
    ASSERT_EQ(made.exit_code, 0) << made.err;
    WsClient stream(port(), trimmed(made.out));
    std::int64_t id = -1;
    for (const json& entry : tokens()) {
      if (entry.at("label") == "liam") id = entry.at("id").get<std::int64_t>();
    }
    const CommandResult revoked = token_tool({"revoke", std::to_string(id)});
    ASSERT_EQ(revoked.exit_code, 0) << revoked.err;
    const auto [after, code] = time_to_close(stream);
    EXPECT_EQ(code, 4401);
    EXPECT_LT(after, 1s);
  }
  // Expired while open.
  {
    const HttpReply made = admin().post(
        "/api/v1/tokens", json{{"role", "viewer"}, {"label", "mia"}, {"expires_in_s", 600}});
    ASSERT_EQ(made.status, 201) << made.body;
    WsClient stream(port(), made.json().at("token").get<std::string>());
    expire_in_store(made.json().at("id").get<std::int64_t>(),
                    static_cast<std::int64_t>(std::time(nullptr)) - 1);
    const auto [after, code] = time_to_close(stream);
    EXPECT_EQ(code, 4401);
    EXPECT_LT(after, 1s);
  }
  // Another token's stream stays open through all of it.
  WsClient other(port(), viewer_token());
  other.send(json{{"op", "ping"}, {"id", "open"}});
  EXPECT_TRUE(other.read_until("pong").has_value());
}

}  // namespace
}  // namespace mobot::testing
