// The audit trail against a real mobotd (docs/api.md, "The audit trail"): every command a client
// sends is a `command` event of the run with the token's label and the client's address, on disk
// before the command's reply; a drive is its start and its stop; a refused command is not in it.
#include "support/api_test.h"

namespace mobot::testing {
namespace {

class AuditApiTest : public ServerSuite<AuditApiTest> {
 protected:
  // The run's `command` events, oldest first.
  static std::vector<json> commands() {
    const HttpReply reply =
        viewer().get("/api/v1/runs/" + std::to_string(current_run_id(viewer())) + "/events");
    EXPECT_EQ(reply.status, 200) << reply.body;
    std::vector<json> found;
    if (reply.status != 200) return found;
    for (const auto& event : reply.json()) {
      if (event.value("kind", "") == "command") found.push_back(event.at("detail"));
    }
    return found;
  }

  static std::vector<json> commands_named(const std::string& name) {
    std::vector<json> found;
    for (auto& command : commands()) {
      if (command.value("command", "") == name) found.push_back(command);
    }
    return found;
  }
};

TEST_F(AuditApiTest, ARestCommandIsInTheRunBeforeItsReplyWithWhoSentIt) {
  const HttpClient carol = admin().with_token(create_token(admin(), "operator", "carol"));
  const std::size_t before = commands_named("POST /api/v1/goals").size();
  const HttpReply goal = carol.post("/api/v1/goals", json{{"x", 6.0}, {"y", 7.5}});
  ASSERT_EQ(goal.status, 201) << goal.body;
  // Read at once after the reply: it is committed already.
  const auto goals = commands_named("POST /api/v1/goals");
  ASSERT_EQ(goals.size(), before + 1);
  const json& audited = goals.back();
  EXPECT_EQ(audited.at("label"), "carol");
  EXPECT_EQ(audited.at("role"), "operator");
  EXPECT_EQ(audited.at("via"), "rest");
  EXPECT_EQ(audited.at("status"), 201);
  EXPECT_EQ(audited.at("request").at("x"), 6.0);
  EXPECT_NE(audited.at("address").get<std::string>().find("127.0.0.1:"), std::string::npos);
  EXPECT_GT(audited.at("token_id").get<std::int64_t>(), 0);
  const std::string goal_id = std::to_string(goal.json().at("id").get<std::int64_t>());
  ASSERT_EQ(carol.del("/api/v1/goals/" + goal_id).status, 200);
  EXPECT_EQ(commands_named("DELETE /api/v1/goals/" + goal_id).size(), 1U);
  // The e-stop, and a token made: commands like any other.
  ASSERT_EQ(carol.post("/api/v1/estop", json{{"engaged", true}}).status, 200);
  ASSERT_EQ(carol.post("/api/v1/estop", json{{"engaged", false}}).status, 200);
  const auto estops = commands_named("POST /api/v1/estop");
  ASSERT_GE(estops.size(), 2U);
  EXPECT_EQ(estops.back().at("request").at("engaged"), false);
  create_token(admin(), "viewer", "dave");
  const auto tokens = commands_named("POST /api/v1/tokens");
  ASSERT_FALSE(tokens.empty());
  EXPECT_EQ(tokens.back().at("request").at("label"), "dave");
  EXPECT_EQ(tokens.back().at("label"), "admin (--token)");
  // What the admin was given is not in the run: only what was asked.
  EXPECT_FALSE(tokens.back().contains("token"));
  ASSERT_EQ(carol.post("/api/v1/operator", json{{"action", "release"}}).status, 200);
  EXPECT_EQ(commands_named("POST /api/v1/operator").back().at("request").at("action"), "release");
}

TEST_F(AuditApiTest, ARefusedOrAnonymousCommandIsNotInTheTrail) {
  const std::size_t before = commands().size();
  EXPECT_EQ(operator_client().post("/api/v1/goals", json{{"x", "far"}}).status, 400);
  EXPECT_EQ(viewer().post("/api/v1/goals", json{{"x", 1.0}, {"y", 1.0}}).status, 403);
  EXPECT_EQ(anonymous().post("/api/v1/estop", json{{"engaged", true}}).status, 401);
  EXPECT_EQ(operator_client().post("/api/v1/goals", "{").status, 400);
  EXPECT_EQ(commands().size(), before);
}

TEST_F(AuditApiTest, ADriveIsItsStartAndItsStopOverRestAndStream) {
  const HttpClient erin = admin().with_token(create_token(admin(), "operator", "erin"));
  const std::size_t starts = commands_named("teleop_start").size();
  for (int i = 0; i < 10; ++i) {
    ASSERT_EQ(erin.post("/api/v1/teleop", json{{"v", 0.1}, {"w", 0.0}, {"ttl_ms", 500}}).status,
              200);
  }
  ASSERT_EQ(erin.post("/api/v1/teleop", json{{"v", 0.0}, {"w", 0.0}}).status, 200);
  ASSERT_TRUE(wait_until([&] { return commands_named("teleop_start").size() == starts + 1; }, 5s));
  ASSERT_TRUE(wait_until(
      [&] {
        const auto stops = commands_named("teleop_stop");
        return !stops.empty() && stops.back().at("label") == "erin";
      },
      5s));
  EXPECT_EQ(commands_named("teleop_stop").back().at("reason"), "released");
  EXPECT_EQ(commands_named("teleop_start").back().at("via"), "rest");
  ASSERT_EQ(erin.post("/api/v1/operator", json{{"action", "release"}}).status, 200);

  // Over the stream: the drive ends when the stream closes, and the robot stops then.
  {
    WsClient stream(port(), erin.token());
    for (int seq = 1; seq <= 5; ++seq) {
      stream.send(json{{"op", "teleop"}, {"v", 0.2}, {"w", 0.0}, {"ttl_ms", 1000}, {"seq", seq}});
      const auto reply = stream.read_until("teleop");
      ASSERT_TRUE(reply.has_value());
      EXPECT_EQ(reply->at("seq"), seq);
    }
    stream.send(json{{"op", "estop"}, {"engaged", false}});
    const auto estop = stream.read_until("estop");
    ASSERT_TRUE(estop.has_value());
    EXPECT_EQ(estop->at("engaged"), false);
  }
  ASSERT_TRUE(wait_until(
      [&] {
        const auto stops = commands_named("teleop_stop");
        return !stops.empty() && stops.back().at("reason") == "stream_closed";
      },
      5s));
  const auto stream_estops = commands_named("estop");
  ASSERT_FALSE(stream_estops.empty());
  EXPECT_EQ(stream_estops.back().at("via"), "stream");
  EXPECT_EQ(stream_estops.back().at("label"), "erin");
  ASSERT_TRUE(wait_until(
      [] { return robot_state(viewer()).at("mode").get<std::string>() != "teleop"; }, 2s));
}

}  // namespace
}  // namespace mobot::testing
