// The operator lock against a real mobotd (docs/api.md, "The operator lock"): alice drives over
// the stream; bob, another operator, is refused (409 operator_busy) for teleop and goals and sees
// who drives; e-stop and cancelling stay open to him; when alice's stream closes the lock lapses
// and bob drives; an admin takes the lock over from him. GET /api/v1/clients lists the open
// connections with who they are and what they were sent.
#include "support/api_test.h"

namespace mobot::testing {
namespace {

class OperatorLockApiTest : public ServerSuite<OperatorLockApiTest> {};

TEST_F(OperatorLockApiTest, OnePersonDrivesAndTheLockLapsesWithTheirStream) {
  const HttpClient alice = admin().with_token(create_token(admin(), "operator", "alice"));
  const HttpClient bob = admin().with_token(create_token(admin(), "operator", "bob"));
  EXPECT_TRUE(viewer().get("/api/v1/operator").json().at("holder").is_null());
  {
    WsClient stream(port(), create_token(admin(), "viewer", "unused"));  // a viewer's stream
    stream.send(json{{"op", "teleop"}, {"v", 0.1}, {"w", 0.0}});
    const auto refused = stream.read_until("error");
    ASSERT_TRUE(refused.has_value());
    EXPECT_EQ(refused->at("code"), "forbidden");
  }
  // Her stream and her REST requests are one person: one token.
  auto alice_stream = std::make_unique<WsClient>(port(), alice.token());
  alice_stream->send(json{{"op", "teleop"}, {"v", 0.1}, {"w", 0.0}, {"ttl_ms", 300}});
  const auto applied = alice_stream->read_until("teleop");
  ASSERT_TRUE(applied.has_value());
  const json holder = viewer().get("/api/v1/operator").json().at("holder");
  ASSERT_FALSE(holder.is_null());
  EXPECT_EQ(holder.at("label"), "alice");
  EXPECT_EQ(holder.at("role"), "operator");
  EXPECT_NE(holder.at("address").get<std::string>().find("127.0.0.1:"), std::string::npos);

  // Bob is refused, and nothing he sent changed the robot's mode or the lock.
  const HttpReply teleop = bob.post("/api/v1/teleop", json{{"v", 0.2}, {"w", 0.0}});
  EXPECT_EQ(teleop.status, 409) << teleop.body;
  EXPECT_EQ(teleop.json().at("error").at("code"), "operator_busy");
  EXPECT_NE(teleop.json().at("error").at("message").get<std::string>().find("alice"),
            std::string::npos);
  const HttpReply goal = bob.post("/api/v1/goals", json{{"x", 3.0}, {"y", 3.0}});
  EXPECT_EQ(goal.status, 409) << goal.body;
  EXPECT_EQ(bob.post("/api/v1/operator", json{{"action", "take_over"}}).status, 403);
  EXPECT_EQ(bob.post("/api/v1/operator", json{{"action", "release"}}).status, 409);
  EXPECT_EQ(viewer().get("/api/v1/operator").json().at("holder").at("label"), "alice");
  // Stopping is his to do.
  EXPECT_EQ(bob.post("/api/v1/estop", json{{"engaged", true}}).status, 200);
  EXPECT_EQ(bob.post("/api/v1/estop", json{{"engaged", false}}).status, 200);

  // Alice's stream closes: the lock lapses with it, and bob drives.
  alice_stream.reset();
  ASSERT_TRUE(wait_until(
      [] { return viewer().get("/api/v1/operator").json().at("holder").is_null(); }, 2s));
  EXPECT_EQ(bob.post("/api/v1/teleop", json{{"v", 0.0}, {"w", 0.0}}).status, 200);
  EXPECT_EQ(viewer().get("/api/v1/operator").json().at("holder").at("label"), "bob");
  EXPECT_EQ(alice.post("/api/v1/teleop", json{{"v", 0.0}, {"w", 0.0}}).status, 409);

  // An admin takes over; bob is refused; the admin lets go.
  const HttpReply taken = admin().post("/api/v1/operator", json{{"action", "take_over"}});
  ASSERT_EQ(taken.status, 200) << taken.body;
  EXPECT_EQ(taken.json().at("holder").at("token_id"), 0);
  EXPECT_EQ(bob.post("/api/v1/teleop", json{{"v", 0.0}, {"w", 0.0}}).status, 409);
  EXPECT_TRUE(admin().post("/api/v1/operator", json{{"action", "release"}}).json().at("holder").is_null());
}

TEST_F(OperatorLockApiTest, TheAdminSeesEveryConnectionWithWhoItIs) {
  const HttpClient carol = admin().with_token(create_token(admin(), "viewer", "carol"));
  WsClient stream(port(), carol.token());
  stream.send(json{{"op", "subscribe"}, {"topics", {"pose", "status"}}});
  ASSERT_TRUE(stream.read_until("pose").has_value());
  EXPECT_EQ(viewer().get("/api/v1/clients").status, 403);
  json mine;
  ASSERT_TRUE(wait_until(
      [&] {
        for (const json& client : admin().get("/api/v1/clients").json()) {
          if (client.at("kind") == "stream" && client.at("label") == "carol") mine = client;
        }
        return !mine.is_null() && mine.at("bytes_sent").get<double>() > 0;
      },
      3s))
      << admin().get("/api/v1/clients").body;
  EXPECT_EQ(mine.at("role"), "viewer");
  EXPECT_EQ(mine.at("topics"), json({"pose", "status"}));
  EXPECT_NE(mine.at("address").get<std::string>().find("127.0.0.1:"), std::string::npos);
  EXPECT_GT(mine.at("since").get<double>(), 1.6e9);
  EXPECT_EQ(mine.at("dropped"), 0);
  // The admin's own request is there too, as an http connection.
  bool admin_seen = false;
  for (const json& client : admin().get("/api/v1/clients").json()) {
    admin_seen = admin_seen || (client.at("kind") == "http" && client.at("role") == "admin");
  }
  EXPECT_TRUE(admin_seen);
}

}  // namespace
}  // namespace mobot::testing
