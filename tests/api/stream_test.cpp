// The WebSocket stream: hello, subscribe/unsubscribe, every topic in JSON and the bulk ones in the
// README binary layout, rates (in robot time), thinning, ping, errors that keep the connection,
// teleop over the stream, authentication, and a slow reader that must not hurt anybody else.
#include <numbers>
#include <set>

#include "support/api_test.h"

namespace mobot::testing {
namespace {

class StreamTest : public ServerSuite<StreamTest> {
 protected:
  void SetUp() override {
    ServerSuite::SetUp();
    ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", false}}).status, 200);
    ASSERT_EQ(operator_client().post("/api/v1/sim/reset", json::object()).status, 200);
  }
  void TearDown() override {
    operator_client().post("/api/v1/estop", json{{"engaged", false}});
    ServerSuite::TearDown();
  }

  static WsClient subscribed(const std::vector<std::string>& topics,
                             const std::string& encoding = "", const std::string& token = "") {
    WsClient client(port(), token.empty() ? viewer_token() : token);
    json request{{"op", "subscribe"}, {"topics", topics}};
    if (!encoding.empty()) request["encoding"] = encoding;
    client.send(request);
    const auto reply = client.read_until("subscribed", 5s);
    EXPECT_TRUE(reply.has_value()) << "no subscribed reply";
    if (reply) {
      EXPECT_EQ(reply->at("topics"), json(topics));
    }
    return client;
  }

  static std::int64_t active_map_id() {
    for (const auto& map : viewer().get("/api/v1/maps").json()) {
      if (map.at("active").get<bool>()) return map.at("id").get<std::int64_t>();
    }
    return -1;
  }
};

// Collects the JSON frames of `topic` for `duration` of wall time.
std::vector<json> collect(WsClient& client, const std::string& topic,
                          std::chrono::milliseconds duration) {
  std::vector<json> frames;
  for (const auto& frame : client.read_all_for(duration)) {
    if (!frame.text()) continue;
    const json message = json::parse(frame.payload, nullptr, false);
    if (message.is_object() && message.value("topic", "") == topic) frames.push_back(message);
  }
  return frames;
}

void expect_envelope(const json& frame, const std::string& topic) {
  EXPECT_EQ(frame.at("topic"), topic);
  EXPECT_TRUE(frame.at("t").is_number()) << frame.dump().substr(0, 200);
  EXPECT_TRUE(frame.at("seq").is_number_unsigned()) << frame.dump().substr(0, 200);
  EXPECT_GE(frame.at("seq").get<std::uint64_t>(), 1U);
  ASSERT_TRUE(frame.at("wall_us").is_number_integer());
  const double now_us =
      std::chrono::duration<double, std::micro>(std::chrono::system_clock::now().time_since_epoch())
          .count();
  EXPECT_NEAR(frame.at("wall_us").get<double>(), now_us, 60e6)
      << "wall_us is not Unix microseconds";
  EXPECT_TRUE(frame.contains("data"));
}

TEST_F(StreamTest, HelloAdvertisesEveryTopic) {
  WsClient client(port(), viewer_token());
  const json& hello = client.hello();
  EXPECT_EQ(hello.at("op"), "hello");
  EXPECT_EQ(hello.at("version"), 1);
  std::map<std::string, json> topics;
  for (const auto& topic : hello.at("topics")) {
    ASSERT_TRUE(topic.at("name").is_string());
    ASSERT_TRUE(topic.at("rate_hz").is_number());
    ASSERT_TRUE(topic.at("encodings").is_array());
    EXPECT_FALSE(topics.count(topic.at("name"))) << "advertised twice: " << topic.dump();
    topics[topic.at("name")] = topic;
  }
  for (const char* name : {"pose", "odom", "scan", "sonar", "map", "status", "events", "truth"}) {
    ASSERT_TRUE(topics.count(name)) << name << " is not advertised: " << hello.dump();
  }
  EXPECT_DOUBLE_EQ(topics["pose"].at("rate_hz").get<double>(), 50.0);
  EXPECT_DOUBLE_EQ(topics["scan"].at("rate_hz").get<double>(), 10.0);
  EXPECT_DOUBLE_EQ(topics["status"].at("rate_hz").get<double>(), 1.0);
  EXPECT_EQ(topics["scan"].at("encodings"), json({"json", "binary"}));
  EXPECT_EQ(topics["map"].at("encodings"), json({"json", "binary"}));
  EXPECT_EQ(topics["pose"].at("encodings"), json({"json"}));
}

TEST_F(StreamTest, SubscribeAndUnsubscribe) {
  WsClient client = subscribed({"pose", "status"});
  EXPECT_TRUE(client.read_until("pose", 5s).has_value());
  client.send({{"op", "unsubscribe"}, {"topics", {"pose"}}});
  const auto reply = client.read_until("unsubscribed", 5s);
  ASSERT_TRUE(reply.has_value());
  EXPECT_EQ(reply->at("topics"), json({"pose"}));
  // After the reply no pose frame comes any more, while status still does.
  const auto rest = client.read_all_for(1500ms);
  int status = 0;
  for (const auto& frame : rest) {
    if (!frame.text()) continue;
    const json message = frame.json();
    EXPECT_NE(message.value("topic", ""), "pose") << "a pose frame after unsubscribing";
    if (message.value("topic", "") == "status") ++status;
  }
  EXPECT_GE(status, 3) << "status (1 Hz robot time, x10) stopped too";

  // Unsubscribing what is not subscribed removes nothing.
  client.send({{"op", "unsubscribe"}, {"topics", {"pose", "scan"}}});
  const auto none = client.read_until("unsubscribed", 5s);
  ASSERT_TRUE(none.has_value());
  EXPECT_EQ(none->at("topics"), json::array());
}

TEST_F(StreamTest, PoseAtFiftyHertzOfRobotTime) {
  WsClient client = subscribed({"pose"});
  const std::vector<json> frames = collect(client, "pose", 1500ms);
  ASSERT_GE(frames.size(), 50U);
  for (const auto& frame : {frames.front(), frames.back()}) {
    expect_envelope(frame, "pose");
    const json& data = frame.at("data");
    for (const char* key : {"x", "y", "theta", "v", "w"})
      EXPECT_TRUE(data.at(key).is_number()) << key;
    ASSERT_TRUE(data.at("cov").is_array());
    EXPECT_EQ(data.at("cov").size(), 9U);
    EXPECT_NEAR(data.at("x").get<double>(), 2.0, 0.05);
    EXPECT_NEAR(data.at("y").get<double>(), 7.5, 0.05);
  }
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const auto dseq =
        frames[i].at("seq").get<std::int64_t>() - frames[i - 1].at("seq").get<std::int64_t>();
    ASSERT_GE(dseq, 1) << "seq must increase";
    const double dt = frames[i].at("t").get<double>() - frames[i - 1].at("t").get<double>();
    EXPECT_NEAR(dt, 0.02 * static_cast<double>(dseq), 1e-3) << "one pose per 20 ms control period";
  }
  const double span_t = frames.back().at("t").get<double>() - frames.front().at("t").get<double>();
  const auto span_seq =
      frames.back().at("seq").get<std::int64_t>() - frames.front().at("seq").get<std::int64_t>();
  ASSERT_GT(span_t, 1.0) << "robot time hardly advanced (x10 for 1.5 s)";
  EXPECT_NEAR(static_cast<double>(span_seq) / span_t, 50.0, 2.5);
  // A client that reads has (nearly) every frame.
  EXPECT_GE(static_cast<double>(frames.size()), 0.5 * static_cast<double>(span_seq + 1));
}

TEST_F(StreamTest, ScanAsBinaryFrames) {
  WsClient client = subscribed({"scan"});
  const auto frame = client.read_binary(5s);
  ASSERT_TRUE(frame.has_value()) << "no binary scan frame";
  const std::string& bytes = frame->payload;
  const BinaryHeader header = parse_binary_header(bytes);
  EXPECT_EQ(header.magic, "MBT1");
  EXPECT_EQ(header.topic_id, 1);
  ASSERT_EQ(header.header_bytes, 32);
  EXPECT_GE(header.seq, 1U);
  EXPECT_GT(header.t, 0.0);
  const double now_us =
      std::chrono::duration<double, std::micro>(std::chrono::system_clock::now().time_since_epoch())
          .count();
  EXPECT_NEAR(static_cast<double>(header.wall_us), now_us, 60e6);
  const std::size_t body = header.header_bytes;
  const float angle_min = read_le<float>(bytes, body);
  const float angle_increment = read_le<float>(bytes, body + 4);
  const float range_min = read_le<float>(bytes, body + 8);
  const float range_max = read_le<float>(bytes, body + 12);
  const float sensor_x = read_le<float>(bytes, body + 16);
  const float sensor_y = read_le<float>(bytes, body + 20);
  const float sensor_theta = read_le<float>(bytes, body + 24);
  const auto count = read_le<std::uint32_t>(bytes, body + 28);
  EXPECT_EQ(count, 361U);
  ASSERT_EQ(bytes.size(), body + 32 + 4 * static_cast<std::size_t>(count));
  EXPECT_NEAR(angle_min, -std::numbers::pi / 2, 1e-3);
  EXPECT_NEAR(angle_increment, std::numbers::pi / 360, 1e-5);
  EXPECT_NEAR(range_min, 0.4, 1e-5);
  EXPECT_NEAR(range_max, 80.0, 1e-3);
  // The laser sits 0.2 m ahead of the base at (2, 7.5, 0).
  EXPECT_NEAR(sensor_x, 2.2, 0.05);
  EXPECT_NEAR(sensor_y, 7.5, 0.05);
  EXPECT_NEAR(sensor_theta, 0.0, 0.02);
  int valid = 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    const float range = read_le<float>(bytes, body + 32 + 4 * i);
    if (range >= range_min && range <= range_max) ++valid;
  }
  EXPECT_GT(valid, 300) << "inside the office nearly every beam hits a wall";
  // Beam 360 looks left (north) at the corridor wall y = 8.5, 1 m away.
  EXPECT_NEAR(read_le<float>(bytes, body + 32 + 4 * 360), 1.0, 0.1);

  // The next scan is one laser period (0.1 s of robot time) later.
  const auto next = client.read_binary(5s);
  ASSERT_TRUE(next.has_value());
  const BinaryHeader next_header = parse_binary_header(next->payload);
  EXPECT_GT(next_header.seq, header.seq);
  EXPECT_NEAR(next_header.t - header.t, 0.1 * static_cast<double>(next_header.seq - header.seq),
              0.021);
}

TEST_F(StreamTest, ScanAsJson) {
  WsClient client = subscribed({"scan"}, "json");
  const auto frame = client.read_until("scan", 5s);
  ASSERT_TRUE(frame.has_value());
  expect_envelope(*frame, "scan");
  const json& data = frame->at("data");
  for (const char* key : {"angle_min", "angle_increment", "range_min", "range_max"}) {
    EXPECT_TRUE(data.at(key).is_number()) << key;
  }
  ASSERT_TRUE(data.at("ranges").is_array());
  EXPECT_EQ(data.at("ranges").size(), 361U);
  EXPECT_NEAR(data.at("angle_min").get<double>(), -std::numbers::pi / 2, 1e-3);
  EXPECT_NEAR(data.at("sensor_pose").at("x").get<double>(), 2.2, 0.05);
  EXPECT_NEAR(data.at("sensor_pose").at("y").get<double>(), 7.5, 0.05);
  EXPECT_TRUE(data.at("sensor_pose").at("theta").is_number());
  // With encoding json nothing binary arrives.
  for (const auto& other : client.read_all_for(500ms)) EXPECT_FALSE(other.binary());
}

TEST_F(StreamTest, BulkEncodingDoesNotAffectJsonTopics) {
  WsClient client = subscribed({"pose", "scan"}, "binary");
  bool pose_text = false;
  bool scan_binary = false;
  for (const auto& frame : client.read_all_for(1s)) {
    if (frame.binary()) {
      scan_binary = scan_binary || parse_binary_header(frame.payload).topic_id == 1;
    } else if (frame.text()) {
      pose_text = pose_text || frame.json().value("topic", "") == "pose";
    }
  }
  EXPECT_TRUE(pose_text);
  EXPECT_TRUE(scan_binary);
}

TEST_F(StreamTest, MapOnSubscribeAsBinary) {
  WsClient client = subscribed({"map"});
  const auto frame = client.read_binary(10s);
  ASSERT_TRUE(frame.has_value()) << "no map frame on subscribe";
  const std::string& bytes = frame->payload;
  const BinaryHeader header = parse_binary_header(bytes);
  EXPECT_EQ(header.magic, "MBT1");
  EXPECT_EQ(header.topic_id, 2);
  const std::size_t body = header.header_bytes;
  const auto width = read_le<std::uint32_t>(bytes, body);
  const auto height = read_le<std::uint32_t>(bytes, body + 4);
  EXPECT_EQ(width, 400U);
  EXPECT_EQ(height, 300U);
  EXPECT_NEAR(read_le<float>(bytes, body + 8), 0.05F, 1e-6);
  EXPECT_FLOAT_EQ(read_le<float>(bytes, body + 12), 0.0F);
  EXPECT_FLOAT_EQ(read_le<float>(bytes, body + 16), 0.0F);
  EXPECT_EQ(read_le<std::uint32_t>(bytes, body + 24), static_cast<std::uint32_t>(active_map_id()));
  EXPECT_EQ(read_le<std::uint32_t>(bytes, body + 28), 0U);
  ASSERT_EQ(bytes.size(), body + 32 + static_cast<std::size_t>(width) * height);
  const auto cell = [&](std::uint32_t col, std::uint32_t row) {
    return static_cast<unsigned char>(
        bytes[body + 32 + static_cast<std::size_t>(row) * width + col]);
  };
  EXPECT_EQ(cell(0, 0), 100) << "the outer wall is occupied";
  EXPECT_EQ(cell(40, 150), 0) << "(2, 7.5) in the corridor is free";
  for (std::uint32_t i = 0; i < width * height; i += 997) {
    const unsigned value = cell(i % width, i / width);
    EXPECT_TRUE(value <= 100 || value == 255) << value;
  }
}

TEST_F(StreamTest, MapOnSubscribeAsJson) {
  WsClient client = subscribed({"map"}, "json");
  const auto frame = client.read_until("map", 10s);
  ASSERT_TRUE(frame.has_value());
  expect_envelope(*frame, "map");
  const json& data = frame->at("data");
  EXPECT_EQ(data.at("id"), active_map_id());
  EXPECT_EQ(data.at("width"), 400);
  EXPECT_EQ(data.at("height"), 300);
  EXPECT_DOUBLE_EQ(data.at("resolution").get<double>(), 0.05);
  EXPECT_DOUBLE_EQ(data.at("origin").at("x").get<double>(), 0.0);
  ASSERT_EQ(data.at("data").size(), 120000U);
  EXPECT_EQ(data.at("data").at(0), 100);
  EXPECT_EQ(data.at("data").at(150 * 400 + 40), 0);
}

TEST_F(StreamTest, StatusOncePerRobotSecond) {
  WsClient client = subscribed({"status"});
  const std::vector<json> frames = collect(client, "status", 1500ms);
  ASSERT_GE(frames.size(), 3U) << "1 Hz of robot time at x10";
  expect_envelope(frames.front(), "status");
  const json& data = frames.front().at("data");
  for (const char* key :
       {"t", "mode", "pose", "velocity", "localization", "kinematics", "estop", "sensors"}) {
    EXPECT_TRUE(data.contains(key)) << key;
  }
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const double dt = frames[i].at("t").get<double>() - frames[i - 1].at("t").get<double>();
    EXPECT_NEAR(dt, 1.0, 0.05);
  }
}

TEST_F(StreamTest, EstopEventsArrive) {
  WsClient client = subscribed({"events"});
  ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", true}}).status, 200);
  auto event = client.read_until("events", 5s);
  ASSERT_TRUE(event.has_value()) << "no event after the e-stop";
  expect_envelope(*event, "events");
  EXPECT_EQ(event->at("data").at("kind"), "estop");
  EXPECT_EQ(event->at("data").at("detail"), (json{{"engaged", true}}));
  EXPECT_TRUE(event->at("data").at("t").is_number());
  // The audit trail's record of the command follows the change it made.
  event = client.read_until("events", 5s);
  ASSERT_TRUE(event.has_value());
  EXPECT_EQ(event->at("data").at("kind"), "command");
  EXPECT_EQ(event->at("data").at("detail").at("command"), "POST /api/v1/estop");
  ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", false}}).status, 200);
  event = client.read_until("events", 5s);
  ASSERT_TRUE(event.has_value());
  EXPECT_EQ(event->at("data").at("detail"), (json{{"engaged", false}}));
}

TEST_F(StreamTest, TruthOdomAndSonar) {
  WsClient client = subscribed({"truth", "odom", "sonar"});
  std::map<std::string, json> seen;
  for (const auto& frame : client.read_all_for(1s)) {
    if (!frame.text()) continue;
    const json message = frame.json();
    if (message.contains("topic")) seen[message.at("topic")] = message;
  }
  ASSERT_TRUE(seen.count("truth"));
  ASSERT_TRUE(seen.count("odom"));
  ASSERT_TRUE(seen.count("sonar"));
  const json& truth = seen["truth"].at("data");
  EXPECT_NEAR(truth.at("pose").at("x").get<double>(), 2.0, 0.05);
  EXPECT_TRUE(truth.at("collisions").is_number_integer());
  const json& odom = seen["odom"].at("data");
  for (const char* key : {"x", "y", "theta", "v", "w"})
    EXPECT_TRUE(odom.at(key).is_number()) << key;
  const json& sonar = seen["sonar"].at("data");
  ASSERT_EQ(sonar.at("readings").size(), 8U);
  for (const auto& reading : sonar.at("readings")) {
    for (const char* key : {"x", "y", "theta", "cone", "range", "range_min", "range_max"}) {
      EXPECT_TRUE(reading.at(key).is_number()) << key;
    }
  }
}

TEST_F(StreamTest, MaxRateThinsATopicForThisClient) {
  WsClient thinned(port(), viewer_token());
  thinned.send({{"op", "subscribe"}, {"topics", {"pose"}}, {"max_rate_hz", 5}});
  ASSERT_TRUE(thinned.read_until("subscribed").has_value());
  WsClient full = subscribed({"pose"});
  const std::vector<json> slow = collect(thinned, "pose", 1500ms);
  const std::vector<json> fast = collect(full, "pose", 300ms);
  EXPECT_GE(slow.size(), 4U);
  EXPECT_LE(slow.size(), 12U) << "5 Hz for 1.5 s";
  for (std::size_t i = 1; i < slow.size(); ++i) {
    EXPECT_GE(
        slow[i].at("wall_us").get<std::int64_t>() - slow[i - 1].at("wall_us").get<std::int64_t>(),
        150000);
  }
  EXPECT_GT(fast.size(), 3 * slow.size()) << "the other client was thinned too";
}

TEST_F(StreamTest, PingPong) {
  WsClient client(port(), viewer_token());
  for (const json& id : {json(42), json("abc"), json({{"nested", true}})}) {
    client.send({{"op", "ping"}, {"id", id}});
    const auto pong = client.read_until("pong", 5s);
    ASSERT_TRUE(pong.has_value());
    EXPECT_EQ(pong->at("id"), id);
    ASSERT_TRUE(pong->at("t").is_number());
    // t is the robot clock: between two reads of GET /robot around it.
    EXPECT_GE(pong->at("t").get<double>(), 0.0);
    EXPECT_LE(pong->at("t").get<double>(), robot_time(viewer()) + 1e-9);
  }
  // A WebSocket-level ping gets a pong frame with the same payload.
  client.send_raw(encode_client_frame(WsOp::kPing, "are you there"));
  bool ponged = false;
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (!ponged && std::chrono::steady_clock::now() < deadline) {
    const auto frame = client.read(1s);
    if (frame && frame->opcode == WsOp::kPong) {
      EXPECT_EQ(frame->payload, "are you there");
      ponged = true;
    }
  }
  EXPECT_TRUE(ponged);
}

TEST_F(StreamTest, BadMessagesGetAnErrorAndKeepTheConnection) {
  WsClient client(port(), viewer_token());
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"op":"dance"})", "unknown_op"},
      {R"({"op":"subscribe","topics":["nonsense"]})", "unknown_topic"},
      {R"({"op":"subscribe","topics":"pose"})", "invalid_topics"},
      {R"({"op":"subscribe"})", "invalid_topics"},
      {R"({"op":"subscribe","topics":[1,2]})", "invalid_topics"},
      {R"({"op":"subscribe","topics":["pose"],"encoding":"xml"})", "invalid_encoding"},
      {R"({"op":"subscribe","topics":["pose"],"max_rate_hz":0})", "invalid_field"},
      {R"({"op":"subscribe","topics":["pose"],"max_rate_hz":"fast"})", "invalid_field"},
      {R"({"op":"unsubscribe"})", "invalid_topics"},
      {"{not json", "malformed_json"},
      {"", "malformed_json"},
      {R"({"op":"ping","id":NaN})", "malformed_json"},
      {"[1,2,3]", "missing_op"},
      {R"({"op":5})", "missing_op"},
      {R"({"topics":["pose"]})", "missing_op"},
      {std::string(30000, '[') + std::string(30000, ']'), "missing_op"},
  };
  for (const auto& [message, code] : cases) {
    client.send_text(message);
    const auto error = client.read_until("error", 5s);
    ASSERT_TRUE(error.has_value()) << "no error for " << message.substr(0, 80);
    EXPECT_EQ(error->at("code"), code) << message.substr(0, 80);
    EXPECT_TRUE(error->at("message").is_string());
    client.send({{"op", "ping"}, {"id", 1}});
    ASSERT_TRUE(client.read_until("pong", 5s).has_value())
        << "the connection died after " << message.substr(0, 80);
  }
  // A binary client message is an error too, not a disconnect.
  client.send_raw(encode_client_frame(WsOp::kBinary, "\x01\x02"));
  const auto error = client.read_until("error", 5s);
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->at("code"), "unsupported_message");

  // Known topics of a mixed request are subscribed, the unknown ones reported.
  client.send({{"op", "subscribe"}, {"topics", {"pose", "bogus"}}});
  const auto reply = client.read_until("subscribed", 5s);
  ASSERT_TRUE(reply.has_value());
  EXPECT_EQ(reply->at("topics"), json({"pose"}));
  const auto unknown = client.read_until("error", 5s);
  ASSERT_TRUE(unknown.has_value());
  EXPECT_EQ(unknown->at("code"), "unknown_topic");
  EXPECT_NE(unknown->at("message").get<std::string>().find("bogus"), std::string::npos);
  EXPECT_TRUE(client.read_until("pose", 5s).has_value());
}

TEST_F(StreamTest, FragmentedMessagesAreReassembled) {
  WsClient client(port(), viewer_token());
  const std::string message = R"({"op":"ping","id":"fragmented"})";
  client.send_raw(encode_client_frame(WsOp::kText, message.substr(0, 10), false));
  client.send_raw(encode_client_frame(WsOp::kContinuation, message.substr(10, 10), false));
  client.send_raw(encode_client_frame(WsOp::kContinuation, message.substr(20), true));
  const auto pong = client.read_until("pong", 5s);
  ASSERT_TRUE(pong.has_value());
  EXPECT_EQ(pong->at("id"), "fragmented");
}

TEST_F(StreamTest, TeleopOverTheStream) {
  WsClient client(port(), operator_token());
  const json start = sim_truth(viewer()).at("pose");
  client.send({{"op", "teleop"}, {"v", 5.0}, {"w", 0.0}, {"ttl_ms", 300}});
  const auto reply = client.read_until("teleop", 5s);
  ASSERT_TRUE(reply.has_value());
  EXPECT_DOUBLE_EQ(reply->at("v").get<double>(), 1.3);
  EXPECT_DOUBLE_EQ(reply->at("w").get<double>(), 0.0);
  const double t0 = robot_time(viewer());
  while (robot_time(viewer()) < t0 + 1.0) {
    client.send({{"op", "teleop"}, {"v", 0.5}, {"w", 0.0}});
    ASSERT_TRUE(client.read_until("teleop", 5s).has_value());
    // A joystick's pace: a client is held to 100 messages a second.
    std::this_thread::sleep_for(20ms);
  }
  const json moved = sim_truth(viewer()).at("pose");
  EXPECT_GT(moved.at("x").get<double>() - start.at("x").get<double>(), 0.2);

  // The same rules as REST: invalid input and e-stop are refused.
  client.send({{"op", "teleop"}, {"v", 500.0}, {"w", 0.0}});
  auto error = client.read_until("error", 5s);
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->at("code"), "invalid_field");
  client.send({{"op", "teleop"}, {"v", 0.5}});
  error = client.read_until("error", 5s);
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->at("code"), "missing_field");
  client.send({{"op", "teleop"}, {"v", 0.5}, {"w", 0.0}, {"ttl_ms", 5000}});
  error = client.read_until("error", 5s);
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->at("code"), "invalid_field");
  ASSERT_EQ(operator_client().post("/api/v1/estop", json{{"engaged", true}}).status, 200);
  client.send({{"op", "teleop"}, {"v", 0.5}, {"w", 0.0}});
  error = client.read_until("error", 5s);
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->at("code"), "estop_engaged");
}

TEST_F(StreamTest, ViewerCannotTeleopOverTheStream) {
  WsClient client(port(), viewer_token());
  const json start = sim_truth(viewer()).at("pose");
  for (int i = 0; i < 10; ++i) {
    client.send({{"op", "teleop"}, {"v", 1.0}, {"w", 0.0}, {"ttl_ms", 1000}});
    const auto error = client.read_until("error", 5s);
    ASSERT_TRUE(error.has_value());
    EXPECT_EQ(error->at("code"), "forbidden");
  }
  ASSERT_TRUE(wait_robot_time(viewer(), 0.5));
  const json end = sim_truth(viewer()).at("pose");
  EXPECT_NEAR(end.at("x").get<double>(), start.at("x").get<double>(), 0.005)
      << "a viewer moved the robot";
  client.send({{"op", "ping"}, {"id", 2}});
  EXPECT_TRUE(client.read_until("pong", 5s).has_value());
}

TEST_F(StreamTest, UpgradeNeedsAValidToken) {
  EXPECT_EQ(ws_upgrade_status(port(), "/api/v1/stream"), 401);
  EXPECT_EQ(ws_upgrade_status(port(), "/api/v1/stream?token="), 401);
  EXPECT_EQ(ws_upgrade_status(port(), "/api/v1/stream?token=wrong"), 401);
  EXPECT_EQ(ws_upgrade_status(port(), "/api/v1/stream?other=" + viewer_token()), 401);
  EXPECT_EQ(ws_upgrade_status(port(), "/api/v1/stream?token=" + viewer_token()), 101);
  EXPECT_EQ(ws_upgrade_status(port(), "/api/v1/stream?token=" + operator_token()), 101);
  EXPECT_EQ(ws_upgrade_status(port(), "/api/v1/stream?x=1&token=" + server().token()), 101);
  try {
    WsClient refused(port(), "wrong");
    ADD_FAILURE() << "a wrong token was accepted";
  } catch (const WsHandshakeError& error) {
    EXPECT_EQ(error.status(), 401);
    EXPECT_NE(error.body().find("unauthorized"), std::string::npos) << error.body();
  }
  // The WebSocket is only at /api/v1/stream.
  EXPECT_EQ(ws_upgrade_status(port(), "/api/v1/robot?token=" + viewer_token()), 404);
  // A plain GET of the stream path is not a WebSocket.
  EXPECT_EQ(viewer().get("/api/v1/stream").status, 404);
}

TEST_F(StreamTest, UpgradeNeedsKeyAndVersion) {
  for (const std::string& headers :
       {std::string("Sec-WebSocket-Version: 13\r\n"),
        std::string(
            "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 8\r\n")}) {
    RawConnection connection(port());
    connection.send(
        "GET /api/v1/stream?token=" + viewer_token() +
        " HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n" + headers +
        "\r\n");
    const auto reply = connection.read_http_reply(5s);
    ASSERT_TRUE(reply.has_value());
    EXPECT_EQ(reply->status, 400) << headers;
    EXPECT_EQ(reply->error_code(), "bad_upgrade");
  }
  // The accept key follows RFC 6455 (the example of its section 1.3).
  RawConnection connection(port());
  connection.send(
      "GET /api/v1/stream?token=" + viewer_token() +
      " HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
      "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n");
  const auto reply = connection.read_http_reply(5s);
  ASSERT_TRUE(reply.has_value());
  EXPECT_EQ(reply->status, 101);
  EXPECT_EQ(reply->header("sec-websocket-accept"), "s3pPLMBiTxaQ9kYGzzhZRbK+xOo=");
}

TEST_F(StreamTest, ClientCloseIsAnswered) {
  WsClient client(port(), viewer_token());
  client.send_raw(encode_client_frame(WsOp::kClose, std::string("\x03\xe8", 2)));
  std::optional<WsFrame> frame;
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (std::chrono::steady_clock::now() < deadline) {
    frame = client.read(1s);
    if (frame && frame->opcode == WsOp::kClose) break;
    if (!client.is_open()) break;
  }
  ASSERT_TRUE(frame.has_value() && frame->opcode == WsOp::kClose) << "no close frame in reply";
  EXPECT_EQ(frame->close_code(), 1000);
  EXPECT_FALSE(client.read(2s).has_value());
  EXPECT_FALSE(client.is_open()) << "the server kept the connection after the close handshake";
}

// ---- a slow reader must not slow down the robot or the other clients -------------------------

class SlowReaderTest : public ServerSuite<SlowReaderTest> {
 public:
  // Real time: 50 pose frames per second, so that the reading client has slack to spare and any
  // seq gap is the server's doing.
  static MobotdProcess::Options server_options() {
    MobotdProcess::Options options;
    options.time_scale = 1.0;
    return options;
  }
};

std::uint64_t metric(const HttpClient& client, const std::string& name) {
  const std::string body = client.get("/metrics").body;
  const auto at = body.find("\n" + name + " ");
  if (at == std::string::npos) return 0;
  return std::stoull(body.substr(at + name.size() + 2));
}

TEST_F(SlowReaderTest, ASlowReaderDoesNotDelayOthersOrTheControlLoop) {
  const std::vector<std::string> everything = {"pose", "odom",   "scan",   "sonar",
                                               "map",  "status", "events", "truth"};
  std::vector<std::unique_ptr<WsClient>> slow;
  for (const std::string encoding : {"binary", "json", "binary", "json"}) {
    // A tiny receive buffer, and then it never reads again.
    slow.push_back(std::make_unique<WsClient>(port(), viewer_token(), 2048));
    slow.back()->send({{"op", "subscribe"}, {"topics", everything}, {"encoding", encoding}});
  }
  // Re-publish the map (0.1 MB binary, ~0.3 MB JSON per frame) until the slow readers' sockets
  // are full and the server starts dropping their frames.
  const std::string office =
      "/api/v1/maps/" +
      std::to_string(viewer().get("/api/v1/maps").json().at(0).at("id").get<int>()) + "/activate";
  ASSERT_TRUE(wait_until(
      [&] {
        EXPECT_EQ(operator_client().post(office, "").status, 200);
        return metric(viewer(), "mobot_stream_frames_dropped_total") > 0;
      },
      20s, 50ms))
      << "the slow readers never fell behind: the test did not test anything";

  WsClient reader(port(), viewer_token());
  reader.send({{"op", "subscribe"}, {"topics", {"pose"}}});
  ASSERT_TRUE(reader.read_until("subscribed", 5s).has_value());
  const double wall_window_s = 3.0;
  const auto started = std::chrono::steady_clock::now();
  std::vector<json> frames;
  int rest_calls = 0;
  std::chrono::milliseconds slowest_rest{0};
  while (std::chrono::steady_clock::now() <
         started + std::chrono::duration<double>(wall_window_s)) {
    for (const auto& frame : reader.read_all_for(100ms)) {
      if (!frame.text()) continue;
      const json message = frame.json();
      if (message.value("topic", "") == "pose") frames.push_back(message);
    }
    // REST stays quick too, and the map keeps being re-published to the slow readers.
    const auto before = std::chrono::steady_clock::now();
    EXPECT_EQ(viewer().get("/api/v1/robot").status, 200);
    EXPECT_EQ(operator_client().post(office, "").status, 200);
    slowest_rest = std::max(slowest_rest, std::chrono::duration_cast<std::chrono::milliseconds>(
                                              std::chrono::steady_clock::now() - before));
    ++rest_calls;
  }
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  ASSERT_GE(frames.size(), 2U);
  int gaps = 0;
  for (std::size_t i = 1; i < frames.size(); ++i) {
    if (frames[i].at("seq").get<std::uint64_t>() !=
        frames[i - 1].at("seq").get<std::uint64_t>() + 1)
      ++gaps;
  }
  EXPECT_EQ(gaps, 0) << "the reading client lost pose frames";
  const double robot_s = frames.back().at("t").get<double>() - frames.front().at("t").get<double>();
  // The control loop kept its 50 Hz of real time: robot time kept up with the wall clock.
  EXPECT_GT(robot_s, 0.8 * (wall_s - 0.3))
      << "robot time " << robot_s << " s in " << wall_s << " s";
  EXPECT_GE(static_cast<double>(frames.size()), 0.8 * 50.0 * (wall_s - 0.3));
  EXPECT_LT(slowest_rest, std::chrono::milliseconds(1000));
  EXPECT_GT(rest_calls, 5);
}

}  // namespace
}  // namespace mobot::testing
