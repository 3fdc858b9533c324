// The stream's teleop lease (seq, sent_ms), its e-stop, the audit of a drive's start and stop
// and why it stopped, and the round trip measured from the server's pings.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "api/token_watch.h"
#include "stream_session_harness.h"

namespace mobot::api::test {
namespace {

using namespace std::chrono_literals;

StreamOptions round_trip_every(int interval_ms) {
  StreamOptions options;
  options.round_trip_ping_interval_ms = interval_ms;
  return options;
}

// The next frame whose payload holds `text`, skipping the others (pings, replies).
std::optional<Frame> next_with(Client& client, const std::string& text) {
  while (auto frame = client.read()) {
    if (frame->payload.find(text) != std::string::npos) return frame;
  }
  return std::nullopt;
}

class StreamLeaseTest : public StreamSessionTest {
 protected:
  // Round-trip pings off unless a drive runs: the tests read the frames they expect.
  StreamLeaseTest() : StreamSessionTest(round_trip_every(0)) {}

  std::vector<CommandRecord> commands(const std::string& name) const {
    std::vector<CommandRecord> found;
    for (auto& record : robot_.audit.records()) {
      if (record.command == name) found.push_back(record);
    }
    return found;
  }

  // Waits up to 5 s for the audit trail to hold `count` records of `name`.
  bool wait_for_commands(const std::string& name, std::size_t count) const {
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (commands(name).size() < count) {
      if (std::chrono::steady_clock::now() > deadline) return false;
      std::this_thread::sleep_for(2ms);
    }
    return true;
  }

  std::size_t teleops_accepted() const {
    const auto accepted = robot_.answers.accepted();
    return static_cast<std::size_t>(std::count(accepted.begin(), accepted.end(), "teleop"));
  }
};

TEST_F(StreamLeaseTest, ACommandWhoseSeqIsNotAboveTheLastIsDropped) {
  auto client = open(Role::kOperator);
  client->send_text(R"({"op":"teleop","v":0.2,"w":0,"seq":5,"sent_ms":1000.5})");
  const auto first = next_with(*client, R"("op":"teleop")");
  ASSERT_TRUE(first.has_value());
  EXPECT_NE(first->payload.find(R"("seq":5)"), std::string::npos) << first->payload;
  EXPECT_NE(first->payload.find(R"("sent_ms":1000.5)"), std::string::npos) << first->payload;
  for (const char* stale :
       {R"({"op":"teleop","v":0.9,"w":0,"seq":5})", R"({"op":"teleop","v":0.9,"w":0,"seq":4})",
        R"({"op":"teleop","v":0.9,"w":0,"seq":0})"}) {
    client->send_text(stale);
    const auto refused = next_with(*client, R"("op":"error")");
    ASSERT_TRUE(refused.has_value()) << stale;
    EXPECT_NE(refused->payload.find(R"("code":"stale_seq")"), std::string::npos)
        << refused->payload;
  }
  EXPECT_EQ(teleops_accepted(), 1U) << "a dropped command reached the robot";
  client->send_text(R"({"op":"teleop","v":0.3,"w":0,"seq":6})");
  const auto next = next_with(*client, R"("op":"teleop")");
  ASSERT_TRUE(next.has_value());
  EXPECT_NE(next->payload.find(R"("seq":6)"), std::string::npos) << next->payload;
  EXPECT_EQ(teleops_accepted(), 2U);
  // A command without seq is not ordered, and does not reset the order.
  client->send_text(R"({"op":"teleop","v":0.3,"w":0})");
  ASSERT_TRUE(next_with(*client, R"("op":"teleop")").has_value());
  client->send_text(R"({"op":"teleop","v":0.3,"w":0,"seq":6})");
  EXPECT_TRUE(next_with(*client, R"("code":"stale_seq")").has_value());
  EXPECT_EQ(teleops_accepted(), 3U);
}

// An error reply names the message it answers: a client with an e-stop, teleops and a subscribe
// in flight tells which one was refused without reading the error's words.
TEST_F(StreamLeaseTest, AnErrorReplySaysWhichRequestItRefuses) {
  auto driver = open(Role::kOperator);
  driver->send_text(R"({"op":"teleop","v":0.2,"w":0,"seq":5})");
  ASSERT_TRUE(next_with(*driver, R"("op":"teleop")").has_value());
  const auto expect_error = [](Client& client, const std::string& message, const std::string& code,
                               const std::string& identity) {
    client.send_text(message);
    const auto refused = next_with(client, R"("op":"error")");
    ASSERT_TRUE(refused.has_value()) << message;
    const auto reply = nlohmann::json::parse(refused->payload);
    EXPECT_EQ(reply.at("code"), code) << refused->payload;
    const auto expected = nlohmann::json::parse(identity);
    EXPECT_EQ(reply.value("request_op", nlohmann::json()),
              expected.value("request_op", nlohmann::json()))
        << message << " -> " << refused->payload;
    EXPECT_EQ(reply.value("seq", nlohmann::json()), expected.value("seq", nlohmann::json()))
        << message << " -> " << refused->payload;
  };
  expect_error(*driver, R"({"op":"teleop","v":0.2,"w":0,"seq":4})", "stale_seq",
               R"({"request_op":"teleop","seq":4})");
  expect_error(*driver, R"({"op":"teleop","v":"fast","w":0,"seq":9})", "invalid_field",
               R"({"request_op":"teleop","seq":9})");
  expect_error(*driver, R"({"op":"estop"})", "missing_field", R"({"request_op":"estop"})");
  expect_error(*driver, R"({"op":"subscribe","topics":["nope"]})", "unknown_topic",
               R"({"request_op":"subscribe"})");
  expect_error(*driver, R"({"op":"subscribe","topics":"pose"})", "invalid_topics",
               R"({"request_op":"subscribe"})");
  // Nothing to name: not JSON, no op, an op the protocol does not have.
  expect_error(*driver, R"({"op":)", "malformed_json", "{}");
  expect_error(*driver, R"({"v":1})", "missing_op", "{}");
  expect_error(*driver, R"({"op":"fly"})", "unknown_op", "{}");
  // Refused by the robot, after the control loop had it.
  robot_.answers.refusal =
      DomainError{ErrorKind::kConflict, "estop_engaged", "the e-stop is engaged"};
  expect_error(*driver, R"({"op":"teleop","v":0.2,"w":0,"seq":10})", "estop_engaged",
               R"({"request_op":"teleop","seq":10})");
  expect_error(*driver, R"({"op":"estop","engaged":true})", "estop_engaged",
               R"({"request_op":"estop"})");
  auto viewer = open(Role::kViewer);
  expect_error(*viewer, R"({"op":"estop","engaged":true})", "forbidden",
               R"({"request_op":"estop"})");
}

TEST_F(StreamLeaseTest, EachConnectionHasItsOwnSequence) {
  auto first = open(Role::kOperator);
  first->send_text(R"({"op":"teleop","v":0.2,"w":0,"seq":100})");
  ASSERT_TRUE(next_with(*first, R"("op":"teleop")").has_value());
  first.reset();
  ASSERT_TRUE(wait_for_clients(0));
  auto second = open(Role::kOperator);
  second->send_text(R"({"op":"teleop","v":0.2,"w":0,"seq":1})");
  const auto reply = next_with(*second, R"("op")");
  ASSERT_TRUE(reply.has_value());
  EXPECT_NE(reply->payload.find(R"("seq":1)"), std::string::npos) << reply->payload;
}

TEST_F(StreamLeaseTest, TheEstopOpStopsTheRobotAndIsAudited) {
  auto client = open(Role::kOperator);
  client->send_text(R"({"op":"estop","engaged":true})");
  const auto reply = next_with(*client, R"("op":"estop")");
  ASSERT_TRUE(reply.has_value());
  EXPECT_NE(reply->payload.find(R"("engaged":true)"), std::string::npos) << reply->payload;
  const auto accepted = robot_.answers.accepted();
  EXPECT_EQ(std::count(accepted.begin(), accepted.end(), "set_estop"), 1);
  const auto audited = commands("estop");
  ASSERT_EQ(audited.size(), 1U) << "the reply waits for the audit record";
  EXPECT_EQ(audited[0].via, "stream");
  EXPECT_EQ(audited[0].caller.label, "test");
  EXPECT_EQ(audited[0].caller.role, Role::kOperator);
  EXPECT_EQ(audited[0].address, "127.0.0.1:1");
  EXPECT_EQ(audited[0].request_json, R"({"engaged":true})");
}

TEST_F(StreamLeaseTest, AViewersEstopOrABadOneChangesNothing) {
  auto viewer = open(Role::kViewer);
  viewer->send_text(R"({"op":"estop","engaged":true})");
  EXPECT_TRUE(next_with(*viewer, R"("code":"forbidden")").has_value());
  auto operator_client = open(Role::kOperator);
  operator_client->send_text(R"({"op":"estop"})");
  EXPECT_TRUE(next_with(*operator_client, R"("code":"missing_field")").has_value());
  operator_client->send_text(R"({"op":"estop","engaged":"yes"})");
  EXPECT_TRUE(next_with(*operator_client, R"("code":"invalid_field")").has_value());
  EXPECT_TRUE(robot_.answers.accepted().empty());
  EXPECT_TRUE(robot_.audit.records().empty());
}

TEST_F(StreamLeaseTest, TheEstopIsServedEvenWhileAnotherOperatorHoldsTheLock) {
  auto holder = open(Role::kOperator);
  holder->send_text(R"({"op":"teleop","v":0.2,"w":0})");
  ASSERT_TRUE(next_with(*holder, R"("op":"teleop")").has_value());
  auto other = open(Role::kAdmin);
  other->send_text(R"({"op":"teleop","v":0.2,"w":0})");
  EXPECT_TRUE(next_with(*other, R"("code":"operator_busy")").has_value());
  other->send_text(R"({"op":"estop","engaged":true})");
  EXPECT_TRUE(next_with(*other, R"("op":"estop")").has_value());
}

TEST_F(StreamLeaseTest, ADriveIsAuditedAsItsStartAndItsStop) {
  auto client = open(Role::kOperator);
  for (int i = 0; i < 5; ++i) {
    client->send_text(R"({"op":"teleop","v":0.2,"w":0.1,"ttl_ms":1000})");
    ASSERT_TRUE(next_with(*client, R"("op":"teleop")").has_value());
  }
  ASSERT_TRUE(wait_for_commands("teleop_start", 1));
  client->send_text(R"({"op":"teleop","v":0,"w":0,"ttl_ms":1000})");
  ASSERT_TRUE(next_with(*client, R"("op":"teleop")").has_value());
  ASSERT_TRUE(wait_for_commands("teleop_stop", 1));
  EXPECT_EQ(commands("teleop_start").size(), 1U) << "one start for five commands";
  EXPECT_EQ(commands("teleop_stop")[0].reason, "released");
  EXPECT_EQ(commands("teleop_stop")[0].via, "stream");
  // A standing command with no drive running starts and stops nothing.
  client->send_text(R"({"op":"teleop","v":0,"w":0})");
  ASSERT_TRUE(next_with(*client, R"("op":"teleop")").has_value());
  std::this_thread::sleep_for(50ms);
  EXPECT_EQ(commands("teleop_start").size(), 1U);
  EXPECT_EQ(commands("teleop_stop").size(), 1U);
}

TEST_F(StreamLeaseTest, ALeaseThatLapsesWithNothingHeardIsALinkStall) {
  auto client = open(Role::kOperator);
  client->send_text(R"({"op":"teleop","v":0.2,"w":0,"ttl_ms":100})");
  ASSERT_TRUE(next_with(*client, R"("op":"teleop")").has_value());
  // The client falls silent: it neither sends nor answers the pings at half the ttl.
  ASSERT_TRUE(wait_for_commands("teleop_stop", 1));
  EXPECT_EQ(commands("teleop_stop")[0].reason, "link_stalled");
  // The server pinged it while the lease ran.
  bool pinged = false;
  while (auto frame = client->read()) {
    if (frame->opcode == 0x9U && frame->payload.size() == 8) {
      pinged = true;
      break;
    }
  }
  EXPECT_TRUE(pinged);
}

TEST_F(StreamLeaseTest, ALeaseThatLapsesWhileTheClientTalksIsALapse) {
  auto client = open(Role::kOperator);
  client->send_text(R"({"op":"teleop","v":0.2,"w":0,"ttl_ms":150})");
  ASSERT_TRUE(next_with(*client, R"("op":"teleop")").has_value());
  const auto until = std::chrono::steady_clock::now() + 400ms;
  while (std::chrono::steady_clock::now() < until) {
    client->send_text(R"({"op":"ping","id":1})");
    std::this_thread::sleep_for(20ms);
  }
  ASSERT_TRUE(wait_for_commands("teleop_stop", 1));
  EXPECT_EQ(commands("teleop_stop")[0].reason, "lease_lapsed");
  // The next moving command is a new drive.
  client->send_text(R"({"op":"teleop","v":0.2,"w":0,"ttl_ms":150})");
  EXPECT_TRUE(wait_for_commands("teleop_start", 2));
}

TEST_F(StreamLeaseTest, ADriveWhoseStreamClosesStopsAtOnce) {
  auto client = open(Role::kOperator);
  client->send_text(R"({"op":"teleop","v":0.2,"w":0,"ttl_ms":1000})");
  ASSERT_TRUE(next_with(*client, R"("op":"teleop")").has_value());
  ASSERT_EQ(teleops_accepted(), 1U);
  client.reset();
  ASSERT_TRUE(wait_for_commands("teleop_stop", 1));
  EXPECT_EQ(commands("teleop_stop")[0].reason, "stream_closed");
  EXPECT_EQ(teleops_accepted(), 2U) << "a standing command stops the robot";
  // The lock went with the stream.
  EXPECT_FALSE(hub_.operator_lock().holder(OperatorLock::Clock::now()).has_value());
}

StreamOptions slow_message_rate() {
  StreamOptions options = round_trip_every(0);
  options.client_messages_per_s = 10.0;
  options.client_message_burst = 5.0;
  return options;
}

class StreamRateTest : public StreamSessionTest {
 protected:
  StreamRateTest() : StreamSessionTest(slow_message_rate()) {}
};

TEST_F(StreamRateTest, AFloodIsDroppedButAnEstopInItIsCarriedOut) {
  auto client = open(Role::kOperator);
  for (int i = 0; i < 50; ++i) client->send_text(R"({"op":"ping","id":"flood"})");
  client->send_text(R"({"op":"estop","engaged":true})");
  for (int i = 0; i < 50; ++i) client->send(0x9, "x", true);  // WebSocket pings count too
  std::this_thread::sleep_for(150ms);
  client->send_text(R"({"op":"ping","id":"last"})");
  int pongs = 0;
  int notices = 0;
  int ws_pongs = 0;
  bool estop = false;
  while (auto frame = client->read()) {
    if (frame->payload.find(R"("op":"pong")") != std::string::npos) ++pongs;
    if (frame->payload.find(R"("code":"rate_limited")") != std::string::npos) ++notices;
    if (frame->payload.find(R"("op":"estop")") != std::string::npos) estop = true;
    if (frame->opcode == 0xAU) ++ws_pongs;
    if (frame->payload.find(R"("id":"last")") != std::string::npos) break;
  }
  EXPECT_TRUE(estop) << "the e-stop was dropped with the flood";
  EXPECT_LE(pongs, 8) << "about the burst of five, then the rate";
  EXPECT_LE(ws_pongs, 3);
  EXPECT_EQ(notices, 1) << "one notice a second at most";
  EXPECT_GE(metric(hub_, "mobot_stream_messages_rate_limited_total"), 80U);
  const auto accepted = robot_.answers.accepted();
  EXPECT_EQ(std::count(accepted.begin(), accepted.end(), "set_estop"), 1);
}

TEST_F(StreamLeaseTest, UnderAByteRateCapThePoseGoesAndTheScansThinOut) {
  auto client = open(Role::kViewer);
  client->send_text(R"({"op":"subscribe","topics":["pose","scan"],"max_kbps":200})");
  ASSERT_TRUE(next_with(*client, R"("op":"subscribed")").has_value());
  msgs::LaserScan scan;
  scan.ranges_m.assign(1250, 1.0F);  // about 5 kB a frame: 250 kB/s at 50 Hz, the cap 25 kB/s
  const auto started = std::chrono::steady_clock::now();
  constexpr int kTicks = 50;
  for (int tick = 1; tick <= kTicks; ++tick) {
    const double t_s = tick * 0.02;
    hub_.publish_pose(t_s, {t_s, 0.0, 0.0}, {}, {});
    scan.stamp_s = t_s;
    hub_.publish_scan(scan, {});
    hub_.flush();
    std::this_thread::sleep_until(started + tick * 20ms);
  }
  hub_.publish_pose(9.0, {9.0, 0.0, 0.0}, {}, {});
  hub_.flush();
  int poses = 0;
  int scans = 0;
  while (auto frame = client->read()) {
    if (frame->opcode == 0x2U) ++scans;
    if (frame->payload.find(R"("topic":"pose")") != std::string::npos) {
      ++poses;
      if (frame->payload.find(R"("t":9.0)") != std::string::npos) break;
    }
  }
  EXPECT_EQ(poses, kTicks + 1) << "the state is never thinned";
  // One second at 25 kB/s and the 16 KiB burst: at most about 8 scans of 5 kB, not 50.
  EXPECT_GE(scans, 3);
  EXPECT_LE(scans, 10);
  EXPECT_GE(metric(hub_, "mobot_stream_frames_thinned_total"), 40U);
}

TEST_F(StreamLeaseTest, ABadByteRateCapIsRefusedAndSubscribesNothing) {
  auto client = open(Role::kViewer);
  for (const char* cap : {"-1", "1e9", "\"fast\"", "true"}) {
    client->send_text(std::string(R"({"op":"subscribe","topics":["pose"],"max_kbps":)") + cap +
                      "}");
    const auto reply = next_with(*client, R"("op")");
    ASSERT_TRUE(reply.has_value());
    EXPECT_NE(reply->payload.find(R"("code":"invalid_field")"), std::string::npos)
        << cap << ": " << reply->payload;
  }
}

// A client on a link that got thinner changes its cap alone, without naming its topics again.
TEST_F(StreamLeaseTest, ASubscribeThatOnlyChangesTheCapIsAcknowledged) {
  auto client = open(Role::kViewer);
  client->send_text(R"({"op":"subscribe","topics":[],"max_kbps":64})");
  const auto reply = next_with(*client, R"("op")");
  ASSERT_TRUE(reply.has_value());
  EXPECT_NE(reply->payload.find(R"("op":"subscribed","topics":[])"), std::string::npos)
      << reply->payload;
}

TEST_F(StreamLeaseTest, TheMetricsSayHowOldEachTopicsFramesWereAndWhatEachStreamGot) {
  auto client = open(Role::kViewer);
  client->send_text(R"({"op":"subscribe","topics":["pose"]})");
  ASSERT_TRUE(next_with(*client, R"("op":"subscribed")").has_value());
  for (int tick = 1; tick <= 5; ++tick) {
    hub_.publish_pose(tick * 0.02, {0.0, 0.0, 0.0}, {}, {});
    hub_.flush();
    ASSERT_TRUE(next_with(*client, R"("topic":"pose")").has_value());
  }
  // The age is noted once write_some has returned on the server's thread, which may be just
  // after the client has read the frame.
  std::string text;
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  do {
    text = hub_.metrics_text();
  } while (text.find("mobot_stream_frame_age_seconds_count{topic=\"pose\"} 5") ==
               std::string::npos &&
           std::chrono::steady_clock::now() < deadline);
  EXPECT_NE(text.find("mobot_stream_frame_age_seconds_count{topic=\"pose\"} 5"), std::string::npos)
      << text;
  // On loopback every frame is taken within a second of its publication.
  EXPECT_NE(text.find("mobot_stream_frame_age_seconds_bucket{topic=\"pose\",le=\"1\"} 5"),
            std::string::npos);
  EXPECT_EQ(text.find("mobot_stream_frame_age_seconds_count{topic=\"scan\"}"), std::string::npos)
      << "a topic nobody was sent has no histogram";
  EXPECT_NE(text.find("mobot_stream_client_bytes_sent_total{client=\""), std::string::npos);
  EXPECT_NE(text.find("label=\"test\",address=\"127.0.0.1:1\"}"), std::string::npos);
}

class StreamRoundTripTest : public StreamSessionTest {
 protected:
  StreamRoundTripTest() : StreamSessionTest(round_trip_every(50)) {}
};

TEST_F(StreamRoundTripTest, ThePongOfATimedPingGivesTheClientsRoundTrip) {
  auto client = open(Role::kViewer);
  std::optional<Frame> ping;
  while ((ping = client->read()) && ping->opcode != 0x9U) {
  }
  ASSERT_TRUE(ping.has_value());
  ASSERT_EQ(ping->payload.size(), 8U);
  std::this_thread::sleep_for(30ms);
  client->send_pong(ping->payload);
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  std::optional<double> rtt_ms;
  while (!rtt_ms && std::chrono::steady_clock::now() < deadline) {
    for (const auto& view : hub_.clients().list()) rtt_ms = view.rtt_ms;
    std::this_thread::sleep_for(2ms);
  }
  ASSERT_TRUE(rtt_ms.has_value());
  EXPECT_GE(*rtt_ms, 30.0);
  EXPECT_LT(*rtt_ms, 5000.0);
}

TEST_F(StreamRoundTripTest, PongsThatAreNotAnswersChangeNothing) {
  auto client = open(Role::kViewer);
  client->send_pong("");
  client->send_pong("abc");
  // Eight bytes from the future, and from long ago.
  client->send_pong(std::string(8, '\xff'));
  client->send_pong(std::string(8, '\0'));
  client->send_text(R"({"op":"ping","id":2})");
  ASSERT_TRUE(next_with(*client, R"("op":"pong")").has_value());
  for (const auto& view : hub_.clients().list()) EXPECT_FALSE(view.rtt_ms.has_value());
}

// The fake's tokens: viewer 1, operator 2, admin 3 (stream_session_harness.h).
TEST_F(StreamLeaseTest, AStreamWhoseTokenStopsAuthenticatingIsClosedWith4401) {
  auto viewer = open(Role::kViewer);
  auto operator_client = open(Role::kOperator);
  robot_.tokens.deactivate(1);
  hub_.close_inactive_tokens([this](std::int64_t id) { return robot_.tokens.is_active(id); });
  const std::vector<Frame> frames = viewer->read_to_end();
  ASSERT_FALSE(frames.empty());
  EXPECT_EQ(frames.back().opcode, 0x8U);
  EXPECT_EQ(frames.back().close_code(), 4401U);
  EXPECT_NE(frames.back().payload.find("revoked or expired"), std::string::npos);
  // The other token's stream is untouched.
  operator_client->send_text(R"({"op":"ping","id":"still"})");
  EXPECT_TRUE(next_with(*operator_client, R"("id":"still")").has_value());
  EXPECT_TRUE(wait_for_clients(1));
}

TEST_F(StreamLeaseTest, TheTokenWatchClosesARevokedTokensStreamWithinItsPeriod) {
  TokenWatch watch(io_.get_executor(), hub_, robot_.tokens, 50ms);
  watch.start();
  auto client = open(Role::kOperator);
  client->send_text(R"({"op":"teleop","v":0.2,"w":0,"ttl_ms":1000})");
  ASSERT_TRUE(next_with(*client, R"("op":"teleop")").has_value());
  const auto revoked = std::chrono::steady_clock::now();
  robot_.tokens.deactivate(2);
  const std::vector<Frame> frames = client->read_to_end();
  const auto closed = std::chrono::steady_clock::now();
  ASSERT_FALSE(frames.empty());
  EXPECT_EQ(frames.back().close_code(), 4401U);
  EXPECT_LT(closed - revoked, 500ms);
  // Its drive stopped with it, and the lock went.
  EXPECT_TRUE(wait_for_commands("teleop_stop", 1));
  EXPECT_EQ(commands("teleop_stop")[0].reason, "stream_closed");
  EXPECT_FALSE(hub_.operator_lock().holder(OperatorLock::Clock::now()).has_value());
  watch.stop();
  // The watch's last expiry finds it stopped before the fixture's io threads end.
  std::this_thread::sleep_for(100ms);
}

}  // namespace
}  // namespace mobot::api::test
