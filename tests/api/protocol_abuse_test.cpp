// Hostile or broken clients at the HTTP and WebSocket level: garbage, oversized headers and bodies,
// path tricks, idle connections, protocol violations. The server answers with a 4xx or closes the
// connection, changes nothing, and keeps serving everybody else.
#include "support/api_test.h"

namespace mobot::testing {
namespace {

class ProtocolAbuseTest : public ServerSuite<ProtocolAbuseTest> {
 protected:
  void TearDown() override {
    // Whatever happened, the server still answers.
    const HttpReply health = anonymous().get("/api/v1/health");
    EXPECT_EQ(health.status, 200) << health.body;
    ServerSuite::TearDown();
  }

  std::string authorized_request(const std::string& method, const std::string& target,
                                 const std::string& extra_headers) const {
    return method + " " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nAuthorization: Bearer " +
           operator_token() + "\r\n" + extra_headers + "\r\n";
  }
};

// Bytes that are not an HTTP request get a 400 (RFC 9112 section 3) and the connection closed.
TEST_F(ProtocolAbuseTest, GarbageGetsA400AndAClose) {
  for (const std::string& garbage :
       {std::string("HELLO\r\n\r\n"), std::string("GET\r\n\r\n"),
        std::string("\x16\x03\x01\x02\x00\x01\x00\x01\xfc\x03\x03", 11),
        std::string("GET / HTTP/9.9\r\n\r\n"), std::string(1000, '\0'),
        std::string("GET /api/v1/health HTTP/1.1\r\nBad Header\r\n\r\n")}) {
    RawConnection connection(port());
    ASSERT_TRUE(connection.connected());
    connection.send(garbage);
    const auto reply = connection.read_http_reply(5s);
    ASSERT_TRUE(reply.has_value()) << garbage.substr(0, 20);
    EXPECT_EQ(reply->status, 400) << garbage.substr(0, 20);
    EXPECT_EQ(reply->error_code(), "bad_request") << garbage.substr(0, 20);
    EXPECT_TRUE(connection.closed_by_peer(5s)) << garbage.substr(0, 20);
  }
}

TEST_F(ProtocolAbuseTest, OversizedHeaderIs431) {
  RawConnection connection(port());
  connection.send("GET /api/v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Padding: " +
                  std::string(20000, 'a') + "\r\n\r\n");
  const auto reply = connection.read_http_reply(5s);
  ASSERT_TRUE(reply.has_value());
  EXPECT_EQ(reply->status, 431);
  EXPECT_EQ(reply->error_code(), "header_too_large");
  EXPECT_TRUE(connection.closed_by_peer(5s));
}

TEST_F(ProtocolAbuseTest, BodyOverTheLimitIs413ByContentLength) {
  for (const std::string target :
       {"/api/v1/teleop", "/api/v1/estop", "/api/v1/sim/reset", "/api/v1/tokens"}) {
    RawConnection connection(port());
    // Only the header is sent: the limit is enforced before reading the body.
    connection.send(authorized_request(
        "POST", target, "Content-Type: application/json\r\nContent-Length: 65537\r\n"));
    const auto reply = connection.read_http_reply(5s);
    ASSERT_TRUE(reply.has_value()) << target;
    EXPECT_EQ(reply->status, 413) << target;
    EXPECT_EQ(reply->error_code(), "body_too_large") << target;
    EXPECT_TRUE(connection.closed_by_peer(5s)) << target;
  }
  // Nothing was engaged or reset.
  EXPECT_FALSE(robot_state(viewer()).at("estop").get<bool>());
}

TEST_F(ProtocolAbuseTest, ChunkedBodyOverTheLimitIs413) {
  RawConnection connection(port());
  connection.send(authorized_request(
      "POST", "/api/v1/estop", "Content-Type: application/json\r\nTransfer-Encoding: chunked\r\n"));
  // One chunk announced as 64 KiB + 1 bytes: refused from its size line.
  connection.send("10001\r\n");
  const auto reply = connection.read_http_reply(5s);
  ASSERT_TRUE(reply.has_value());
  EXPECT_EQ(reply->status, 413);
  EXPECT_EQ(reply->error_code(), "body_too_large");
}

TEST_F(ProtocolAbuseTest, ChunkedBodiesWithinTheLimitWork) {
  RawConnection connection(port());
  const std::string body = R"({"engaged":false})";
  char size[16];
  std::snprintf(size, sizeof size, "%zx", body.size());
  connection.send(
      authorized_request("POST", "/api/v1/estop",
                         "Content-Type: application/json\r\nTransfer-Encoding: chunked\r\n") +
      size + "\r\n" + body + "\r\n0\r\n\r\n");
  const auto reply = connection.read_http_reply(5s);
  ASSERT_TRUE(reply.has_value());
  EXPECT_EQ(reply->status, 200) << reply->body;
}

TEST_F(ProtocolAbuseTest, BodyExactlyAtTheLimitIsAccepted) {
  std::string body = R"({"engaged":false})";
  body.append(64 * 1024 - body.size(), ' ');
  ASSERT_EQ(body.size(), 65536U);
  const HttpReply reply = operator_client().post("/api/v1/estop", body);
  EXPECT_EQ(reply.status, 200) << reply.body;
}

TEST_F(ProtocolAbuseTest, OversizedBodySentInFullIsRefused) {
  // A client that sends the whole oversized body anyway gets a 413 (or, if the server closed
  // while it was still sending, a reset), never a 200.
  const std::string body = R"({"v":1.0,"w":0.0,"pad":")" + std::string(100 * 1024, 'x') + "\"}";
  const HttpReply reply = operator_client().post("/api/v1/teleop", body);
  EXPECT_NE(reply.status, 200) << "an oversized teleop was executed";
  if (reply.status != 0) {
    EXPECT_EQ(reply.status, 413);
  }
  ASSERT_TRUE(wait_robot_time(viewer(), 0.5));
  EXPECT_NEAR(robot_state(viewer()).at("velocity").at("v").get<double>(), 0.0, 1e-3);
}

TEST_F(ProtocolAbuseTest, DeeplyNestedJsonIsRefused) {
  const std::string nested = std::string(30000, '[') + std::string(30000, ']');
  HttpReply reply = operator_client().post("/api/v1/teleop", nested);
  EXPECT_EQ(reply.status, 400);
  const std::string objects = [] {
    std::string text;
    for (int i = 0; i < 10000; ++i) text += R"({"a":)";
    text += "1";
    text += std::string(10000, '}');
    return text;
  }();
  reply = operator_client().post("/api/v1/teleop", objects);
  EXPECT_EQ(reply.status, 400);
}

// A number too large for a double (1e999) is out of range: 400 like NaN, on every endpoint.
TEST_F(ProtocolAbuseTest, NumbersTooLargeForADoubleAre400) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"/api/v1/teleop", R"({"v": 1e999, "w": 0})"},
      {"/api/v1/teleop", R"({"v": 0.5, "w": -1e999})"},
      {"/api/v1/teleop", R"({"v": 0.5, "w": 0, "ttl_ms": 1e400})"},
      {"/api/v1/maps",
       R"({"name":"inf","resolution":1e999,"origin":{"x":0,"y":0},"image_base64":"AAAA"})"},
      {"/api/v1/sim/reset", R"({"pose":{"x":1e999,"y":1}})"},
      {"/api/v1/sim/obstacles", R"({"x":1,"y":1,"radius":1e999})"},
  };
  for (const auto& [target, body] : cases) {
    const HttpReply reply = admin().post(target, body);
    EXPECT_EQ(reply.status, 400) << target << " " << body << " -> " << reply.body;
  }
  const HttpReply clock = admin().request("PUT", "/api/v1/sim/clock", R"({"time_scale":1e999})");
  EXPECT_EQ(clock.status, 400) << clock.body;
  EXPECT_FALSE(robot_state(viewer()).at("estop").get<bool>());
  // On the stream: an error reply, and the connection stays.
  WsClient client(port(), operator_token());
  client.send_text(R"({"op":"teleop","v":1e999,"w":0})");
  const auto error = client.read_until("error", 5s);
  ASSERT_TRUE(error.has_value());
  client.send({{"op", "ping"}, {"id", 1}});
  EXPECT_TRUE(client.read_until("pong", 5s).has_value());
}

TEST_F(ProtocolAbuseTest, KeepAliveServesSeveralRequests) {
  RawConnection connection(port());
  for (int i = 0; i < 3; ++i) {
    connection.send("GET /api/v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
    const auto reply = connection.read_http_reply(5s);
    ASSERT_TRUE(reply.has_value()) << "request " << i;
    EXPECT_EQ(reply->status, 200);
  }
  // Pipelined: two requests in one write, two answers in order.
  connection.send(
      "GET /api/v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"
      "GET /api/v1/nope HTTP/1.1\r\nHost: 127.0.0.1\r\nAuthorization: Bearer " +
      operator_token() + "\r\n\r\n");
  const auto first = connection.read_http_reply(5s);
  const auto second = connection.read_http_reply(5s);
  ASSERT_TRUE(first.has_value());
  ASSERT_TRUE(second.has_value());
  EXPECT_EQ(first->status, 200);
  EXPECT_EQ(second->status, 404);
  // An error keeps the connection usable too.
  connection.send("GET /api/v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
  const auto third = connection.read_http_reply(5s);
  ASSERT_TRUE(third.has_value());
  EXPECT_EQ(third->status, 200);
}

TEST_F(ProtocolAbuseTest, PathTraversalIsRefused) {
  for (const std::string target :
       {"/../../../../etc/passwd", "/..%2f..%2f..%2fetc%2fpasswd", "/%2e%2e/%2e%2e/etc/passwd",
        "/assets/../../CMakeLists.txt", "/%2e%2e%2fCMakeLists.txt", "/index.html%00.png"}) {
    const HttpReply reply = anonymous().get(target);
    EXPECT_EQ(reply.status, 404) << target << ": " << reply.body.substr(0, 100);
    EXPECT_EQ(reply.body.find("root:"), std::string::npos) << target;
    EXPECT_EQ(reply.body.find("cmake_minimum_required"), std::string::npos) << target;
  }
}

TEST_F(ProtocolAbuseTest, OddTargetsAreHandled) {
  for (const std::string target :
       {"/api/v1/robot?", "/api/v1/robot?a=1&b", "/api/v1//robot", "/api/v1/robot/",
        "/api/v1/runs/1/trajectory?format=", "/api/v1/maps/%31", "/api/v1/maps/1%2F..",
        "/api/v1/robot#fragment"}) {
    const HttpReply reply = operator_client().get(target);
    EXPECT_GE(reply.status, 200) << target;
    EXPECT_LT(reply.status, 500) << target << ": " << reply.body;
  }
  // A 15 KiB target is answered (not crashed on).
  const HttpReply long_target = operator_client().get("/api/v1/robot?x=" + std::string(15000, 'y'));
  EXPECT_GE(long_target.status, 200);
  EXPECT_LT(long_target.status, 500);
}

TEST_F(ProtocolAbuseTest, IdleAndHalfOpenConnectionsDoNotBlockOthers) {
  std::vector<std::unique_ptr<RawConnection>> idle;
  for (int i = 0; i < 64; ++i) {
    idle.push_back(std::make_unique<RawConnection>(port()));
    ASSERT_TRUE(idle.back()->connected());
    if (i % 2 == 1) idle.back()->send("GET /api/v1/health HTTP/1.1\r\nHost: 12");  // never finished
  }
  for (int i = 0; i < 5; ++i) {
    const auto before = std::chrono::steady_clock::now();
    EXPECT_EQ(operator_client().get("/api/v1/robot").status, 200);
    EXPECT_LT(std::chrono::steady_clock::now() - before, 2s);
  }
  // A body that never arrives does not hold anybody else either.
  RawConnection stalled(port());
  stalled.send(authorized_request("POST", "/api/v1/estop",
                                  "Content-Type: application/json\r\nContent-Length: 100\r\n") +
               R"({"eng)");
  EXPECT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", false}}).status, 200);
  idle.clear();
  EXPECT_EQ(operator_client().get("/api/v1/robot").status, 200);
}

std::uint64_t stream_clients(const HttpClient& client) {
  const std::string body = client.get("/metrics").body;
  const auto at = body.find("\nmobot_stream_clients ");
  return at == std::string::npos ? 0 : std::stoull(body.substr(at + 22));
}

TEST_F(ProtocolAbuseTest, WebSocketProtocolViolationsClose) {
  const std::uint64_t clients_before = stream_clients(viewer());
  struct Case {
    std::string frame;
    int close_code;
  };
  const std::vector<Case> cases = {
      {encode_client_frame(WsOp::kText, R"({"op":"ping"})", true, false), 1002},  // unmasked
      {encode_client_frame(static_cast<WsOp>(0x3), "x"), 1002},                   // reserved opcode
      {encode_client_frame(WsOp::kContinuation, "x"), 1002},            // nothing to continue
      {encode_client_frame(WsOp::kPing, std::string(200, 'p')), 1002},  // long control frame
      {encode_client_frame(WsOp::kPing, "p", false), 1002},             // fragmented control
      // Too big: refused from the frame header (the payload is never sent).
      {encode_client_frame(WsOp::kText, std::string(70 * 1024, ' ')).substr(0, 14), 1009},
      {[] {
         std::string frame = encode_client_frame(WsOp::kText, "{}");
         frame[0] = static_cast<char>(frame[0] | 0x40);  // RSV1 without an extension
         return frame;
       }(),
       1002},
  };
  for (const auto& test : cases) {
    WsClient client(port(), viewer_token());
    client.send_raw(test.frame);
    std::optional<WsFrame> close;
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (std::chrono::steady_clock::now() < deadline && client.is_open()) {
      auto frame = client.read(1s);
      if (frame && frame->opcode == WsOp::kClose) close = frame;
    }
    ASSERT_TRUE(close.has_value())
        << "no close frame for a violation expecting " << test.close_code;
    EXPECT_EQ(close->close_code(), test.close_code);
    EXPECT_FALSE(client.is_open());
  }
  // Other clients did not notice.
  {
    WsClient healthy(port(), viewer_token());
    healthy.send({{"op", "ping"}, {"id", 9}});
    EXPECT_TRUE(healthy.read_until("pong", 5s).has_value());
  }
  // The closed sessions are released, not kept by the server forever.
  EXPECT_TRUE(wait_until([&] { return stream_clients(viewer()) == clients_before; }, 10s))
      << stream_clients(viewer()) << " stream sessions open, " << clients_before << " before";
}

TEST_F(ProtocolAbuseTest, AbruptWebSocketDisconnectsAreCleanedUp) {
  const std::uint64_t clients_before = stream_clients(viewer());
  for (int i = 0; i < 20; ++i) {
    WsClient client(port(), viewer_token());
    client.send({{"op", "subscribe"}, {"topics", {"pose", "scan", "map", "truth"}}});
    // Destroyed without a close handshake.
  }
  // Half a frame, then gone.
  {
    WsClient client(port(), viewer_token());
    client.send_raw(encode_client_frame(WsOp::kText, R"({"op":"ping","id":1})").substr(0, 5));
  }
  EXPECT_TRUE(wait_until([&] { return stream_clients(viewer()) == clients_before; }, 10s))
      << "closed stream sessions are still counted: " << stream_clients(viewer());
}

}  // namespace
}  // namespace mobot::testing
