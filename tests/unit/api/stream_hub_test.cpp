// StreamHub + StreamSession over real loopback sockets: a batch of one flush reaches every client
// in order, flushes during a running write pass are neither reordered nor lost at the newest frame,
// a client that stops reading is bounded and holds nobody back, and closed sessions leave the hub.
#include <gtest/gtest.h>
#include <sys/socket.h>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/write.hpp>
#include <chrono>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "api/api_error.h"
#include "api/robot_port.h"
#include "api/stream_hub.h"
#include "api/stream_session.h"

namespace mobot::api {
namespace {

using boost::asio::ip::tcp;
using namespace std::chrono_literals;

// The stream only asks the port whether the robot is simulated, for snapshots and for teleop.
class FakePort : public RobotPort {
 public:
  std::optional<Role> authenticate(std::string_view) override { return Role::kViewer; }
  std::string backend_name() const override { return "fake"; }
  double uptime_s() const override { return 0.0; }
  RobotSnapshot snapshot() const override { return {}; }
  msgs::Twist teleop(const msgs::Twist& command, int) override { return command; }
  bool set_estop(bool engaged) override { return engaged; }
  navigation::Goal submit_goal(const GoalRequest&) override { throw unsupported(); }
  std::vector<navigation::Goal> list_goals() const override { return {}; }
  std::optional<navigation::Goal> find_goal(std::int64_t) const override { return std::nullopt; }
  navigation::Goal cancel_goal(std::int64_t) override { throw unsupported(); }
  void set_localization_pose(const geometry::Pose2D&, const std::array<double, 9>&) override {}
  std::vector<MapInfo> list_maps() const override { return {}; }
  std::optional<MapInfo> map_info(std::int64_t) const override { return std::nullopt; }
  std::optional<mapping::OccupancyGrid> map_grid(std::int64_t) const override {
    return std::nullopt;
  }
  std::int64_t import_map(const std::string&, const mapping::OccupancyGrid&) override { return 0; }
  void activate_map(std::int64_t) override {}
  void delete_map(std::int64_t) override {}
  std::vector<RunInfo> list_runs() const override { return {}; }
  std::optional<std::vector<TrajectoryPoint>> run_trajectory(std::int64_t) const override {
    return std::nullopt;
  }
  std::optional<std::vector<RunEvent>> run_events(std::int64_t) const override {
    return std::nullopt;
  }
  std::pair<std::int64_t, std::string> create_token(Role, const std::string&) override {
    return {0, ""};
  }
  std::vector<TokenInfo> list_tokens() const override { return {}; }
  bool revoke_token(std::int64_t) override { return false; }
  SweepInfo start_sweep(const SweepRequest&) override { throw unsupported(); }
  std::vector<SweepInfo> list_sweeps() const override { return {}; }
  std::optional<SweepInfo> find_sweep(std::int64_t) const override { return std::nullopt; }
  perception::PointCloud sweep_cloud(std::int64_t) const override { throw unsupported(); }
  mapping::OccupancyGrid sweep_obstacle_map(std::int64_t) const override { throw unsupported(); }
  void delete_sweep(std::int64_t) override { throw unsupported(); }
  bool is_simulated() const override { return true; }
  std::vector<WorldInfo> list_worlds() const override { return {}; }
  SimTruth sim_truth() const override { return {}; }
  void sim_reset(const SimResetRequest&) override {}
  void set_time_scale(double) override {}
  int add_sim_obstacle(double, double, double, double) override { return 0; }
  bool remove_sim_obstacle(int) override { return false; }
  std::string metrics_text() const override { return ""; }

 private:
  static ApiError unsupported() { return ApiError(400, "unsupported", "not in this fake"); }
};

struct Frame {
  unsigned opcode = 0;
  std::string payload;
};

// A blocking WebSocket client on the test thread.
class Client {
 public:
  Client(boost::asio::io_context& io, const tcp::endpoint& server, int receive_buffer = 0)
      : socket_(io) {
    socket_.open(tcp::v4());
    if (receive_buffer > 0) {
      socket_.set_option(boost::asio::socket_base::receive_buffer_size(receive_buffer));
    }
    socket_.connect(server);
    const timeval timeout{5, 0};
    ::setsockopt(socket_.native_handle(), SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  }

  void send_text(const std::string& text, bool masked = true) {
    std::string frame;
    frame.push_back(static_cast<char>(0x81));
    frame.push_back(static_cast<char>((masked ? 0x80 : 0x00) | text.size()));
    if (masked) frame.append(4, '\0');  // a zero mask leaves the payload as it is
    frame += text;
    boost::asio::write(socket_, boost::asio::buffer(frame));
  }

  // The next frame, or nullopt on a closed connection or after the 5 s receive time-out.
  std::optional<Frame> read() {
    std::array<unsigned char, 10> header{};
    if (!read_exactly(header.data(), 2)) return std::nullopt;
    std::uint64_t length = header[1] & 0x7FU;
    if (length == 126 || length == 127) {
      const std::size_t extra = length == 126 ? 2 : 8;
      if (!read_exactly(header.data() + 2, extra)) return std::nullopt;
      length = 0;
      for (std::size_t i = 0; i < extra; ++i) length = (length << 8) | header[2 + i];
    }
    Frame frame{header[0] & 0x0FU, std::string(length, '\0')};
    if (!read_exactly(frame.payload.data(), frame.payload.size())) return std::nullopt;
    return frame;
  }

  // Reads until a text frame containing `text`.
  bool read_until(const std::string& text) {
    while (auto frame = read()) {
      if (frame->payload.find(text) != std::string::npos) return true;
    }
    return false;
  }

 private:
  bool read_exactly(void* data, std::size_t bytes) {
    boost::system::error_code error;
    boost::asio::read(socket_, boost::asio::buffer(data, bytes), error);
    return !error;
  }

  tcp::socket socket_;
};

std::int64_t json_int_after(const std::string& text, const std::string& key) {
  const auto at = text.find(key);
  if (at == std::string::npos) return -1;
  return std::strtoll(text.c_str() + at + key.size(), nullptr, 10);
}

std::uint64_t metric(const StreamHub& hub, const std::string& name) {
  const std::string text = hub.metrics_text();
  const auto at = text.find("\n" + name + " ");
  if (at == std::string::npos) return 0;
  return std::stoull(text.substr(at + name.size() + 2));
}

class StreamHubTest : public ::testing::Test {
 protected:
  StreamHubTest()
      : hub_(StreamOptions{}),
        work_(boost::asio::make_work_guard(io_)),
        acceptor_(io_, tcp::endpoint(boost::asio::ip::make_address("127.0.0.1"), 0)) {
    hub_.set_executor(io_.get_executor(), 2);
    for (int i = 0; i < 2; ++i) threads_.emplace_back([this] { io_.run(); });
  }

  // The test's clients are gone by now: their sessions see the connection end and leave the hub,
  // and the io threads run out of work once the last of them is released.
  ~StreamHubTest() override {
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (metric(hub_, "mobot_stream_clients") > 0 &&
           std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(5ms);
    }
    EXPECT_EQ(metric(hub_, "mobot_stream_clients"), 0U) << "sessions outlived their clients";
    work_.reset();
    while (!io_.stopped() && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(5ms);
    }
    io_.stop();
    for (auto& thread : threads_) thread.join();
  }

  // A client whose server side is a started session, subscribed to `topics` in binary.
  std::unique_ptr<Client> connect(const std::string& topics, int receive_buffer = 0) {
    auto client = std::make_unique<Client>(client_io_, acceptor_.local_endpoint(), receive_buffer);
    tcp::socket server_side(boost::asio::make_strand(io_));
    acceptor_.accept(server_side);
    std::make_shared<StreamSession>(std::move(server_side), hub_, port_, Role::kViewer, "")
        ->start();
    EXPECT_TRUE(client->read_until(R"("op":"hello")"));
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

  FakePort port_;
  StreamHub hub_;
  boost::asio::io_context io_;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work_;
  tcp::acceptor acceptor_;
  std::vector<std::thread> threads_;
  boost::asio::io_context client_io_;
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

}  // namespace
}  // namespace mobot::api
