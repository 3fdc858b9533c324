// StreamHub + StreamSession over real loopback sockets: a batch of one flush reaches every client
// in order, flushes during a running write pass are neither reordered nor lost at the newest frame,
// a client that stops reading is bounded and holds nobody back, and closed sessions leave the hub.
// Teleop replies come from the port's Completion on any thread; silent clients are pinged, then
// closed for idleness; a map is encoded outside the hub's lock; a camera client that caps the
// JPEG quality gets the frames compressed again, once per quality asked, with the camera's seq.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "api/frame_codec.h"
#include "api/stream_hub.h"
#include "api/websocket_frames.h"
#include "stream_session_harness.h"

namespace mobot::api {
namespace {

using namespace std::chrono_literals;
using test::Client;
using test::Frame;
using test::metric;

std::int64_t json_int_after(const std::string& text, const std::string& key) {
  const auto at = text.find(key);
  if (at == std::string::npos) return -1;
  return std::strtoll(text.c_str() + at + key.size(), nullptr, 10);
}

class StreamHubTest : public test::StreamSessionTest {
 protected:
  StreamHubTest() = default;
  explicit StreamHubTest(const StreamOptions& options) : test::StreamSessionTest(options) {}

  // A stream peer registered as GET /api/v1/clients would list it.
  StreamPeer peer(const Caller& caller) {
    auto registration = hub_.clients().open("127.0.0.1:1", 0.0);
    const ClientContext client{registration->id(), "127.0.0.1:1"};
    return StreamPeer{caller, client, std::move(registration)};
  }

  // An open client subscribed to `topics` in binary.
  std::unique_ptr<Client> connect(const std::string& topics, int receive_buffer = 0) {
    auto client = open(Role::kViewer, receive_buffer);
    client->send_text(R"({"op":"subscribe","topics":[)" + topics + "]}");
    EXPECT_TRUE(client->read_until(R"("op":"subscribed")"));
    return client;
  }

  void publish_pose(double t_s) {
    hub_.publish_pose(t_s, {t_s, 0.0, 0.0}, {}, {});
    hub_.flush();
  }

  // The pose seqs a client reads until it sees `last`.
  static std::vector<std::int64_t> pose_seqs_until(Client& client, std::int64_t last) {
    std::vector<std::int64_t> seqs;
    while (auto frame = client.read()) {
      if (frame->payload.find(R"("topic":"pose")") == std::string::npos) continue;
      seqs.push_back(json_int_after(frame->payload, R"("seq":)"));
      if (seqs.back() >= last) break;
    }
    return seqs;
  }
};

TEST_F(StreamHubTest, EveryClientGetsEveryTickInOrder) {
  std::vector<std::unique_ptr<Client>> clients;
  for (int i = 0; i < 40; ++i) clients.push_back(connect(R"("pose")"));
  constexpr int kTicks = 50;
  for (int tick = 1; tick <= kTicks; ++tick) {
    publish_pose(tick * 0.02);
    std::this_thread::sleep_for(2ms);
  }
  for (auto& client : clients) {
    const auto seqs = pose_seqs_until(*client, kTicks);
    ASSERT_FALSE(seqs.empty());
    EXPECT_EQ(seqs.back(), kTicks);
    for (std::size_t i = 1; i < seqs.size(); ++i) ASSERT_GT(seqs[i], seqs[i - 1]);
  }
  EXPECT_GE(metric(hub_, "mobot_stream_frames_sent_total"), 40U);
}

TEST_F(StreamHubTest, FlushesDuringAPassKeepOrderAndTheNewestFrame) {
  std::vector<std::unique_ptr<Client>> clients;
  for (int i = 0; i < 200; ++i) clients.push_back(connect(R"("pose")"));
  // Back to back: most flushes find the previous batch still being written.
  constexpr int kTicks = 500;
  for (int tick = 1; tick <= kTicks; ++tick) publish_pose(tick * 0.02);
  for (auto& client : clients) {
    const auto seqs = pose_seqs_until(*client, kTicks);
    ASSERT_FALSE(seqs.empty());
    EXPECT_EQ(seqs.back(), kTicks) << "the newest frame always goes out";
    for (std::size_t i = 1; i < seqs.size(); ++i) ASSERT_GT(seqs[i], seqs[i - 1]);
  }
}

TEST_F(StreamHubTest, AClientThatStopsReadingIsBoundedAndHoldsNobodyBack) {
  auto stalled = connect(R"("scan")", 4096);
  auto reader = connect(R"("scan")");
  msgs::LaserScan scan;
  scan.ranges_m.assign(50000, 1.0F);  // 200 kB a frame: the stalled socket fills at once
  constexpr int kTicks = 30;
  const auto started = std::chrono::steady_clock::now();
  for (int tick = 1; tick <= kTicks; ++tick) {
    scan.stamp_s = tick * 0.02;
    hub_.publish_scan(scan, {});
    hub_.flush();
    // The reader keeps up; binary scan frames carry their seq at byte 8.
    std::optional<Frame> frame;
    while ((frame = reader->read()) && frame->opcode != 0x2) {
    }
    ASSERT_TRUE(frame.has_value()) << "the reader starved at tick " << tick;
    std::uint64_t seq = 0;
    std::memcpy(&seq, frame->payload.data() + 8, sizeof seq);
    EXPECT_EQ(seq, static_cast<std::uint64_t>(tick));
  }
  EXPECT_LT(std::chrono::steady_clock::now() - started, 5s);
  EXPECT_GT(metric(hub_, "mobot_stream_frames_dropped_total"), 0U)
      << "the stalled client's queue is bounded: old frames are dropped";
}

TEST_F(StreamHubTest, AProtocolViolationClosesTheSessionAndReleasesIt) {
  auto client = connect(R"("pose")");
  EXPECT_EQ(metric(hub_, "mobot_stream_clients"), 1U);
  client->send_text(R"({"op":"ping"})", /*masked=*/false);
  std::optional<Frame> close;
  while (auto frame = client->read()) {
    if (frame->opcode == 0x8) close = frame;
  }
  ASSERT_TRUE(close.has_value());
  ASSERT_GE(close->payload.size(), 2U);
  EXPECT_EQ((static_cast<unsigned char>(close->payload[0]) << 8) |
                static_cast<unsigned char>(close->payload[1]),
            1002);
  EXPECT_EQ(metric(hub_, "mobot_stream_clients"), 0U);
  publish_pose(0.02);  // a flush with nobody attached is harmless
}

TEST_F(StreamHubTest, CloseAllSendsGoingAwayAfterQueuedFrames) {
  auto client = connect(R"("pose")");
  publish_pose(0.02);
  hub_.close_all();
  std::vector<Frame> frames;
  while (auto frame = client->read()) frames.push_back(*frame);
  ASSERT_FALSE(frames.empty());
  EXPECT_EQ(frames.back().opcode, 0x8U) << "nothing follows the close frame";
  EXPECT_EQ((static_cast<unsigned char>(frames.back().payload[0]) << 8) |
                static_cast<unsigned char>(frames.back().payload[1]),
            1001);
}

TEST_F(StreamHubTest, TeleopRepliesFromACompletionOnAnotherThread) {
  robot_.answers.defer = true;
  auto client = open(Role::kOperator);
  client->send_text(R"({"op":"teleop","v":0.5,"w":0.25})");
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (robot_.answers.pending() == 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(1ms);
  }
  std::thread control_loop([this] { EXPECT_EQ(robot_.answers.run_pending(), 1U); });
  control_loop.join();
  std::optional<Frame> reply;
  while ((reply = client->read()) && reply->payload.find(R"("op":"teleop")") == std::string::npos) {
  }
  ASSERT_TRUE(reply.has_value());
  EXPECT_NE(reply->payload.find(R"("v":0.5)"), std::string::npos) << reply->payload;
  EXPECT_NE(reply->payload.find(R"("w":0.25)"), std::string::npos) << reply->payload;
}

TEST_F(StreamHubTest, ARefusedTeleopRepliesWithTheDomainError) {
  robot_.answers.refusal = DomainError{ErrorKind::kConflict, "estop_engaged", "the e-stop is on"};
  auto client = open(Role::kOperator);
  client->send_text(R"({"op":"teleop","v":0.5,"w":0.0})");
  std::optional<Frame> reply;
  while ((reply = client->read()) && reply->payload.find(R"("op":"error")") == std::string::npos) {
  }
  ASSERT_TRUE(reply.has_value());
  EXPECT_NE(reply->payload.find(R"("code":"estop_engaged")"), std::string::npos) << reply->payload;
  EXPECT_NE(reply->payload.find(R"("message":"the e-stop is on")"), std::string::npos)
      << reply->payload;
}

TEST_F(StreamHubTest, ATeleopCompletedAfterTheClientLeftIsHarmless) {
  robot_.answers.defer = true;
  {
    auto client = open(Role::kOperator);
    client->send_text(R"({"op":"teleop","v":0.5,"w":0.0})");
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (robot_.answers.pending() == 0 && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(1ms);
    }
  }
  ASSERT_TRUE(wait_for_clients(0)) << "a pending teleop must not keep its session";
  EXPECT_EQ(robot_.answers.run_pending(), 1U);
}

TEST_F(StreamHubTest, PingAnswersWithTheRobotClock) {
  auto client = open();
  client->send_text(R"({"op":"ping","id":4})");
  std::optional<Frame> pong;
  while ((pong = client->read()) && pong->payload.find(R"("op":"pong")") == std::string::npos) {
  }
  ASSERT_TRUE(pong.has_value());
  EXPECT_NE(pong->payload.find(R"("t":12.5)"), std::string::npos) << pong->payload;
  EXPECT_NE(pong->payload.find(R"("id":4)"), std::string::npos) << pong->payload;
}

TEST_F(StreamHubTest, SimOnlyTopicsAreUnknownWithoutTheSimulator) {
  simulated_ = false;
  auto client = open();
  client->send_text(R"({"op":"subscribe","topics":["truth"]})");
  EXPECT_TRUE(client->read_until(R"("code":"unknown_topic")"));
}

TEST_F(StreamHubTest, AMapSubscriberGetsTheLatestMapAndEveryNewOne) {
  auto grid = std::make_shared<mapping::OccupancyGrid>(4, 3, 0.5, geometry::Pose2D{});
  hub_.publish_map(1.0, grid, 7);
  auto client = connect(R"("map")");
  std::optional<Frame> frame;
  while ((frame = client->read()) && frame->opcode != 0x2) {
  }
  ASSERT_TRUE(frame.has_value()) << "the current map, at subscription";
  const SharedFrame latest = hub_.latest_map_frame(true);
  ASSERT_TRUE(latest.binary);
  EXPECT_EQ(encode_ws_frame(WsOpcode::kBinary, frame->payload), *latest.binary);
  EXPECT_EQ(hub_.latest_map_frame(true).binary, latest.binary) << "encoded once, then kept";

  hub_.publish_map(2.0, grid, 8);
  hub_.flush();
  while ((frame = client->read()) && frame->opcode != 0x2) {
  }
  ASSERT_TRUE(frame.has_value()) << "a newly published map";
  EXPECT_EQ(encode_ws_frame(WsOpcode::kBinary, frame->payload),
            *hub_.latest_map_frame(true).binary);
  EXPECT_NE(hub_.latest_map_frame(true).binary, latest.binary);
  EXPECT_TRUE(hub_.latest_map_frame(false).json) << "and in JSON for a JSON subscriber";
}

// A textured 320 x 240 frame as a camera driver hands it over.
msgs::Image camera_frame(double t_s, int quality) {
  cv::Mat pixels(240, 320, CV_8UC3);
  cv::randu(pixels, cv::Scalar::all(0), cv::Scalar::all(255));
  msgs::Image image;
  image.stamp_s = t_s;
  image.width = pixels.cols;
  image.height = pixels.rows;
  image.encoding = "jpeg";
  image.jpeg_quality = quality;
  cv::imencode(".jpg", pixels, image.data, {cv::IMWRITE_JPEG_QUALITY, quality});
  return image;
}

// The next binary frame's seq and body (the JPEG), or nullopt.
std::optional<std::pair<std::uint64_t, std::string>> next_binary(Client& client) {
  std::optional<Frame> frame;
  while ((frame = client.read()) && frame->opcode != 0x2) {
  }
  if (!frame) return std::nullopt;
  std::uint64_t seq = 0;
  std::memcpy(&seq, frame->payload.data() + 8, sizeof seq);
  return std::pair{seq, frame->payload.substr(kBinaryHeaderBytes)};
}

TEST_F(StreamHubTest, ACameraClientGetsTheQualityItCappedAt) {
  auto full = connect(R"("camera")");
  auto capped = open();
  capped->send_text(R"({"op":"subscribe","topics":["camera"],"camera_quality":20})");
  ASSERT_TRUE(capped->read_until(R"("op":"subscribed")"));
  auto also_capped = open();
  also_capped->send_text(R"({"op":"subscribe","topics":["camera"],"camera_quality":20})");
  ASSERT_TRUE(also_capped->read_until(R"("op":"subscribed")"));
  auto above = open();  // a cap above the camera's own quality changes nothing
  above->send_text(R"({"op":"subscribe","topics":["camera"],"camera_quality":95})");
  ASSERT_TRUE(above->read_until(R"("op":"subscribed")"));

  const msgs::Image image = camera_frame(1.0, 90);
  const std::string original(image.data.begin(), image.data.end());
  for (int tick = 1; tick <= 3; ++tick) {
    hub_.publish_camera(image);
    hub_.flush();
    for (Client* client : {full.get(), above.get()}) {
      const auto frame = next_binary(*client);
      ASSERT_TRUE(frame.has_value()) << "tick " << tick;
      EXPECT_EQ(frame->first, static_cast<std::uint64_t>(tick));
      EXPECT_EQ(frame->second, original);
    }
    const auto low = next_binary(*capped);
    const auto low_too = next_binary(*also_capped);
    ASSERT_TRUE(low.has_value() && low_too.has_value()) << "tick " << tick;
    EXPECT_EQ(low->first, static_cast<std::uint64_t>(tick)) << "the camera's seq, not a new one";
    EXPECT_LT(low->second.size(), original.size() / 2);
    EXPECT_EQ(low->second, low_too->second) << "compressed once for both";
    const std::vector<std::uint8_t> bytes(low->second.begin(), low->second.end());
    const cv::Mat decoded = cv::imdecode(bytes, cv::IMREAD_COLOR);
    EXPECT_EQ(decoded.cols, 320);
    EXPECT_EQ(decoded.rows, 240);
  }
}

TEST_F(StreamHubTest, ABadQualityCapIsRefusedAndSubscribesNothing) {
  auto client = open();
  for (const std::string cap : {"0", "101", "50.5", R"("50")", "-3", "1e99"}) {
    client->send_text(R"({"op":"subscribe","topics":["camera"],"camera_quality":)" + cap + "}");
    EXPECT_TRUE(client->read_until(R"("code":"invalid_field")")) << cap;
  }
  client->send_text(R"({"op":"subscribe","topics":["pose"]})");
  ASSERT_TRUE(client->read_until(R"("op":"subscribed")"));
  hub_.publish_camera(camera_frame(1.0, 90));
  hub_.publish_pose(1.0, {}, {}, {});
  hub_.flush();
  const auto frame = client->read();
  ASSERT_TRUE(frame.has_value());
  EXPECT_EQ(frame->opcode, 0x1U) << "no camera frame: the refused subscriptions took nothing";
  EXPECT_NE(frame->payload.find(R"("topic":"pose")"), std::string::npos) << frame->payload;
}

TEST_F(StreamHubTest, APublishedMapIsEncodedOutsideTheHubLock) {
  // Big enough that its JSON takes far longer than taking the lock.
  auto grid = std::make_shared<mapping::OccupancyGrid>(1500, 1500, 0.05, geometry::Pose2D{});
  const auto encode_started = std::chrono::steady_clock::now();
  const std::string encoded = encode_json_frame("map", {}, map_json(*grid, 1));
  const auto encode_time = std::chrono::steady_clock::now() - encode_started;
  hub_.count_subscription(TopicId::kMap, false, +1);
  std::atomic<bool> publishing{true};
  std::thread map_activation([&] {
    hub_.publish_map(1.0, grid, 1);
    publishing = false;
  });
  std::chrono::steady_clock::duration longest{};
  while (publishing) {
    // metrics_text() takes the hub's lock, as every publication of the control loop does.
    const auto started = std::chrono::steady_clock::now();
    hub_.metrics_text();
    longest = std::max(longest, std::chrono::steady_clock::now() - started);
  }
  map_activation.join();
  hub_.count_subscription(TopicId::kMap, false, -1);
  EXPECT_LT(longest, encode_time / 2)
      << "the lock was held for " << std::chrono::duration<double, std::milli>(longest).count()
      << " ms of a " << std::chrono::duration<double, std::milli>(encode_time).count()
      << " ms encode";
  ASSERT_TRUE(hub_.latest_map_frame(false).json);
  EXPECT_GT(hub_.latest_map_frame(false).json->size(), encoded.size() / 2);
}

// Sessions with short liveness intervals.
class StreamIdleTest : public StreamHubTest {
 protected:
  StreamIdleTest() : StreamHubTest(short_intervals()) {}

  static StreamOptions short_intervals() {
    StreamOptions options;
    options.ping_interval_ms = 100;
    options.idle_timeout_ms = 400;
    return options;
  }
};

TEST_F(StreamIdleTest, ASilentClientIsPingedThenClosedAndReleased) {
  auto client = connect(R"("pose")");
  const auto last_sent = std::chrono::steady_clock::now();
  int pings = 0;
  std::optional<Frame> close;
  while (auto frame = client->read()) {
    if (frame->opcode == 0x9) ++pings;
    if (frame->opcode == 0x8) close = frame;
  }
  const auto silence = std::chrono::steady_clock::now() - last_sent;
  ASSERT_TRUE(close.has_value());
  ASSERT_GE(close->payload.size(), 2U);
  EXPECT_EQ((static_cast<unsigned char>(close->payload[0]) << 8) |
                static_cast<unsigned char>(close->payload[1]),
            1001);
  EXPECT_EQ(close->payload.substr(2), "idle timeout");
  EXPECT_GE(pings, 2) << "pinged every 100 ms of silence before the 400 ms time-out";
  EXPECT_GE(silence, 350ms);
  EXPECT_LT(silence, 3s);
  EXPECT_TRUE(wait_for_clients(0)) << "the idle session left the hub";
}

TEST_F(StreamIdleTest, AClientThatAnswersPingsStaysOpen) {
  auto client = connect(R"("pose")");
  int pings = 0;
  const auto until = std::chrono::steady_clock::now() + 1500ms;
  while (std::chrono::steady_clock::now() < until) {
    const auto frame = client->read();
    ASSERT_TRUE(frame.has_value()) << "the connection ended";
    ASSERT_NE(frame->opcode, 0x8U) << "closed though it answered every ping";
    if (frame->opcode == 0x9) {
      ++pings;
      client->send_pong(frame->payload);
    }
  }
  EXPECT_GE(pings, 5);
  EXPECT_EQ(metric(hub_, "mobot_stream_clients"), 1U);
}

TEST_F(StreamIdleTest, AClientThatKeepsTalkingIsNotPinged) {
  auto client = connect(R"("pose")");
  int pings = 0;
  const auto until = std::chrono::steady_clock::now() + 1000ms;
  while (std::chrono::steady_clock::now() < until) {
    client->send_text(R"({"op":"ping"})");
    const auto frame = client->read();
    ASSERT_TRUE(frame.has_value()) << "the connection ended";
    ASSERT_NE(frame->opcode, 0x8U);
    if (frame->opcode == 0x9) ++pings;
    std::this_thread::sleep_for(30ms);
  }
  // A session that pinged regardless of what it heard would have sent ten; one may slip through a
  // scheduling hiccup of a loaded machine.
  EXPECT_LE(pings, 1);
  EXPECT_EQ(metric(hub_, "mobot_stream_clients"), 1U);
}

}  // namespace
}  // namespace mobot::api
