// Limits against clients that hold or flood the server (docs/api.md, "Limits"): 1000 half-open
// connections (slow-loris) do not stop a normal client from driving and are let go at the header
// timeout; a connection over its request rate is answered 429 with Retry-After and served again
// after it.
#include <sys/resource.h>

#include "support/api_test.h"

namespace mobot::testing {
namespace {

class HardeningTest : public ServerSuite<HardeningTest> {
 protected:
  // The test process holds a thousand sockets of its own: above the default soft limit of 1024.
  static void SetUpTestSuite() {
    rlimit limit{};
    ASSERT_EQ(::getrlimit(RLIMIT_NOFILE, &limit), 0);
    limit.rlim_cur = std::min<rlim_t>(limit.rlim_max, 8192);
    ASSERT_EQ(::setrlimit(RLIMIT_NOFILE, &limit), 0);
    ServerSuite<HardeningTest>::SetUpTestSuite();
  }
};

TEST_F(HardeningTest, AThousandHalfOpenConnectionsDoNotStopAnOperatorDriving) {
  std::vector<std::unique_ptr<RawConnection>> loris;
  for (int i = 0; i < 1000; ++i) {
    loris.push_back(std::make_unique<RawConnection>(port()));
    ASSERT_TRUE(loris.back()->connected()) << "connection " << i;
    // Half of them start a request and never finish it; the others say nothing.
    if (i % 2 == 0) loris.back()->send("GET /api/v1/robot HTTP/1.1\r\nHost: 1");
  }
  const auto opened = std::chrono::steady_clock::now();
  // Meanwhile an operator drives over the stream and over REST, and a viewer reads.
  WsClient stream(port(), operator_token());
  const json start = sim_truth(viewer()).at("pose");
  int answered = 0;
  for (int seq = 1; seq <= 50; ++seq) {
    stream.send(json{{"op", "teleop"}, {"v", 0.3}, {"w", 0.0}, {"ttl_ms", 300}, {"seq", seq}});
    if (stream.read_until("teleop", 2s)) ++answered;
    std::this_thread::sleep_for(20ms);
  }
  EXPECT_EQ(answered, 50);
  for (int i = 0; i < 10; ++i) {
    const auto before = std::chrono::steady_clock::now();
    EXPECT_EQ(operator_client().post("/api/v1/teleop", json{{"v", 0.3}, {"w", 0.0}}).status, 200);
    EXPECT_EQ(viewer().get("/api/v1/robot").status, 200);
    EXPECT_LT(std::chrono::steady_clock::now() - before, 1s);
  }
  const json moved = sim_truth(viewer()).at("pose");
  EXPECT_GT(std::hypot(moved.at("x").get<double>() - start.at("x").get<double>(),
                       moved.at("y").get<double>() - start.at("y").get<double>()),
            0.1);
  // The half-open connections are let go at the header timeout (15 s), the trickling ones too.
  std::this_thread::sleep_until(opened + 14s);
  int trickle = 0;
  for (std::size_t i = 0; i < loris.size(); i += 10) {
    if (loris[i]->send("2")) ++trickle;  // a byte now and then does not keep one open
  }
  EXPECT_GT(trickle, 0);
  std::this_thread::sleep_until(opened + 17s);
  int closed = 0;
  for (auto& connection : loris) closed += connection->closed_by_peer(10ms) ? 1 : 0;
  EXPECT_EQ(closed, 1000);
}

TEST_F(HardeningTest, AConnectionOverItsRequestRateGets429AndThenServiceAgain) {
  RawConnection connection(port());
  ASSERT_TRUE(connection.connected());
  const std::string request = "GET /api/v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
  std::string burst;
  for (int i = 0; i < 600; ++i) burst += request;
  ASSERT_TRUE(connection.send(burst));
  int ok = 0;
  int limited = 0;
  std::string retry_after;
  for (int i = 0; i < 600; ++i) {
    const auto reply = connection.read_http_reply(5s);
    ASSERT_TRUE(reply.has_value()) << "reply " << i;
    if (reply->status == 200) ++ok;
    if (reply->status == 429) {
      ++limited;
      EXPECT_EQ(reply->error_code(), "rate_limited");
      retry_after = reply->header("retry-after");
    }
  }
  EXPECT_GE(ok, 400) << "the burst and what the rate refilled meanwhile";
  EXPECT_GT(limited, 0);
  EXPECT_EQ(ok + limited, 600);
  EXPECT_EQ(retry_after, "1");
  // Another connection was never limited, and this one is served again a second later.
  EXPECT_EQ(viewer().get("/api/v1/robot").status, 200);
  std::this_thread::sleep_for(1s);
  ASSERT_TRUE(connection.send(request));
  const auto again = connection.read_http_reply(5s);
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(again->status, 200);
  EXPECT_NE(admin().get("/metrics").body.find("mobot_http_connections_refused_total 0"),
            std::string::npos);
}

}  // namespace
}  // namespace mobot::testing
