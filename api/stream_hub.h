#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <boost/asio/any_io_executor.hpp>
#include <nlohmann/json.hpp>

#include "api/camera_requality.h"
#include "api/client_registry.h"
#include "api/frame_codec.h"
#include "api/operator_lock.h"
#include "api/ports/camera_port.h"
#include "api/ports/control_port.h"
#include "api/ports/sim_control_port.h"
#include "api/stream_topics.h"
#include "core/mapping/occupancy_grid.h"
#include "core/msgs/ir_ring.h"
#include "core/msgs/laser_scan.h"
#include "core/msgs/odometry.h"
#include "core/msgs/sonar_ring.h"
#include "core/navigation/goal.h"

namespace mobot::api {

struct StreamOptions {
  std::size_t max_frames_per_topic = 4;  // per client; the oldest is dropped beyond it
  std::size_t max_client_message_bytes = 64 * 1024;
  std::size_t max_control_frames = 256;  // replies a client has not read; beyond it, it is closed
  // A client silent this long gets a WebSocket ping, and one silent for idle_timeout_ms is closed
  // (1001) and released: a browser tab that vanished without a FIN must not hold a session. Zero
  // turns the check off.
  int ping_interval_ms = 15000;
  int idle_timeout_ms = 45000;
  // Every client is pinged this often with the time in the ping, and its pong gives the round
  // trip (GET /api/v1/clients); while it drives, at half its lease's ttl, so that a link that
  // stalls is told from an operator who stopped sending. Zero: only while it drives.
  int round_trip_ping_interval_ms = 2000;
  // Messages (text, binary, pings) a client may send: this many a second on average, this many at
  // once. A joystick sends 20 to 60 a second. Beyond it a message is dropped (an error reply at
  // most once a second), except an e-stop, which is always carried out.
  double client_messages_per_s = 100.0;
  double client_message_burst = 200.0;
  std::array<double, kTopicCount> nominal_rate_hz{};  // advertised in the hello
  bool simulated = true;
};

// One publication, encoded once and shared by every session that takes it.
struct SharedFrame {
  std::shared_ptr<const std::string> json;    // complete WebSocket frame (text)
  std::shared_ptr<const std::string> binary;  // complete WebSocket frame (binary), bulk topics only
  std::int64_t wall_us = 0;
  // Camera frames: the JPEG quality the camera compressed this one with (0: not JPEG, no other
  // quality can be made), and, for a copy compressed again for clients that capped their quality
  // (camera_quality), that cap (0: the camera's own frame).
  int source_quality = 0;
  int quality_variant = 0;
};

struct TopicFrame {
  TopicId topic;
  SharedFrame frame;
};

// The publications of one flush, in publication order.
using FrameBatch = std::vector<TopicFrame>;

class StreamSession;

// Fan-out from the robot to the WebSocket sessions. Publishers (the control loop) encode each
// message only in the encodings somebody subscribed to and collect it in a batch; flush() hands
// the batch to the io threads in a single post per thread, and those threads walk the sessions,
// let each take the frames it subscribed to and write them in one gathered, non-blocking write.
// The publisher's cost is thus independent of the number of clients, and nothing here blocks on
// a client: each session keeps a few frames per topic and drops the oldest.
class StreamHub {
 public:
  explicit StreamHub(StreamOptions options);

  // steering_rad: a steered base's steering angle, sent as "steering_rad" when there is one.
  void publish_pose(double t_s, const geometry::Pose2D& pose, const msgs::Twist& velocity,
                    const std::array<double, 9>& covariance,
                    std::optional<double> steering_rad = std::nullopt);
  void publish_odom(const msgs::Odometry& odometry);
  void publish_scan(const msgs::LaserScan& scan, const geometry::Pose2D& sensor_in_map);
  void publish_sonar(const msgs::SonarRing& ring, const geometry::Pose2D& base_in_map);
  void publish_map(double t_s, std::shared_ptr<const mapping::OccupancyGrid> grid,
                   std::int64_t map_id);
  void publish_ir(const msgs::IrRing& ring, const geometry::Pose2D& base_in_map);
  void publish_camera(const msgs::Image& image);
  void publish_target(const TrackingSnapshot& snapshot);
  void publish_costmap(double t_s, const planning::PlanningGrid& costmap, bool local);
  void publish_particles(double t_s, std::span<const estimation::WeightedPose> particles,
                         std::size_t total);
  // While mapping: the whole map so far (for clients that subscribe later) and its changed tiles
  // (for the subscribed ones).
  void publish_map_tiles(double t_s, std::shared_ptr<const mapping::OccupancyGrid> grid,
                         const mapping::MapTileUpdate& tiles);
  void publish_status(const RobotSnapshot& snapshot);
  void publish_event(double t_s, const std::string& kind, const nlohmann::json& detail);
  void publish_truth(const SimTruth& truth);
  // A chunk of a running sweep's cloud (map frame).
  void publish_cloud(double t_s, const CloudChunk& chunk,
                     std::span<const perception::CloudPoint> points);
  // The goal's status (on every change) and the path it follows (when planned or replanned).
  void publish_goal(double t_s, const navigation::Goal& goal);
  void publish_path(double t_s, const navigation::Goal& goal);
  // Sends everything published since the last flush to the sessions, from the io threads.
  void flush();

  // Where flush() writes to the sessions from, and how many threads may share one batch. Without
  // an executor (a hub with no server), publications are discarded at flush.
  void set_executor(boost::asio::any_io_executor executor, unsigned writers);

  void attach(const std::shared_ptr<StreamSession>& session);
  void detach(const StreamSession* session);
  void count_subscription(TopicId topic, bool binary, int delta);
  // Camera subscribers that capped the JPEG quality at `quality` (1..100).
  void count_camera_quality(int quality, int delta);
  // The current map in the given encoding (for a new subscriber), or an empty frame.
  SharedFrame latest_map_frame(bool binary);
  std::string hello_frame() const;
  const StreamOptions& options() const { return options_; }
  void close_all();
  // Closes, with 4401, every stream whose token no longer authenticates (revoked or expired);
  // `is_active` is asked once per token in use.
  void close_inactive_tokens(const std::function<bool(std::int64_t token_id)>& is_active);

  // Who drives: shared by the REST API and the stream sessions of every connection.
  OperatorLock& operator_lock() { return operator_lock_; }
  // Every open connection (GET /api/v1/clients).
  ClientRegistry& clients() { return clients_; }

  void count_sent(std::uint64_t frames, std::uint64_t bytes);
  void count_dropped() { frames_dropped_.fetch_add(1, std::memory_order_relaxed); }
  void count_rate_limited() { messages_rate_limited_.fetch_add(1, std::memory_order_relaxed); }
  void count_thinned() { frames_thinned_.fetch_add(1, std::memory_order_relaxed); }
  // How old a frame of `topic` was (since its publication) when a client's socket took it.
  void note_frame_age(TopicId topic, double age_s);
  std::string metrics_text() const;

 private:
  using SessionList = std::vector<std::shared_ptr<StreamSession>>;
  struct WritePass;
  // The current map and the frames encoded from it so far. `generation` tells an encoding made
  // outside the lock whether its map is still the current one.
  struct LatestMap {
    std::shared_ptr<const mapping::OccupancyGrid> grid;
    std::int64_t id = 0;
    FrameStamp stamp;
    std::uint64_t generation = 0;
    SharedFrame frame;
  };

  bool wanted(TopicId topic) const;
  FrameStamp next_stamp(TopicId topic, double t_s);
  void publish_json(TopicId topic, double t_s, const nlohmann::json& data);
  // A topic with a binary encoding: json_data() gives the JSON data, binary_frame(stamp) the frame.
  template <class JsonData, class BinaryFrame>
  void publish_bulk(TopicId topic, double t_s, JsonData&& json_data, BinaryFrame&& binary_frame);
  template <class JsonData, class BinaryFrame>
  SharedFrame encode_bulk(TopicId topic, const FrameStamp& stamp, JsonData&& json_data,
                          BinaryFrame&& binary_frame);
  SharedFrame encode_camera(const FrameStamp& stamp, const msgs::Image& image);
  // The capped qualities somebody asked for that are below the camera's own.
  std::vector<int> qualities_below(int source_quality) const;
  void publish_requalified(const FrameStamp& stamp,
                           std::vector<std::pair<int, msgs::Image>> variants);
  void complete_map_frame(LatestMap& map, bool binary);
  void distribute(TopicId topic, const SharedFrame& frame);
  void start_pass_locked();
  void run_pass(WritePass& pass);
  void finish_pass();

  StreamOptions options_;
  std::array<std::atomic<int>, kTopicCount> json_subscribers_{};
  std::array<std::atomic<int>, kTopicCount> binary_subscribers_{};
  std::array<std::atomic<std::uint64_t>, kTopicCount> seq_{};
  std::array<std::atomic<int>, 101> camera_quality_subscribers_{};  // by cap, 1..100

  mutable std::mutex mutex_;  // guards everything below
  // Replaced, never modified, on attach and detach: a write pass walks its own snapshot without
  // copying (and reference-counting) every session each tick.
  std::shared_ptr<const SessionList> sessions_ = std::make_shared<const SessionList>();
  FrameBatch pending_;  // published, not yet flushed
  // One pass at a time, so that a client never gets a later tick's frames before an earlier
  // one's; a flush during a pass leaves its frames to the next pass, which starts when this ends.
  bool pass_running_ = false;
  std::size_t passes_started_ = 0;
  std::optional<boost::asio::any_io_executor> executor_;
  unsigned writers_ = 1;
  LatestMap map_;

  std::atomic<std::uint64_t> frames_sent_{0};
  std::atomic<std::uint64_t> bytes_sent_{0};
  std::atomic<std::uint64_t> frames_dropped_{0};
  std::atomic<std::uint64_t> messages_rate_limited_{0};
  std::atomic<std::uint64_t> frames_thinned_{0};
  // mobot_stream_frame_age_seconds: per topic, the count in each bin (the last one open: above
  // every bound) and the sum in microseconds. Two atomic additions a frame: the io threads do this
  // for every frame of every client; the cumulative buckets are summed when /metrics is read.
  static constexpr std::array<double, 11> kAgeBounds_s{0.001, 0.002, 0.005, 0.01, 0.02, 0.05,
                                                       0.1,   0.2,   0.5,   1.0,  2.0};
  struct AgeHistogram {
    std::array<std::atomic<std::uint64_t>, kAgeBounds_s.size() + 1> in_bin{};
    std::atomic<std::uint64_t> sum_us{0};
  };
  std::array<AgeHistogram, kTopicCount> frame_ages_{};
  void append_frame_ages(std::string& out) const;
  std::atomic<std::uint64_t> sessions_opened_{0};
  OperatorLock operator_lock_;
  ClientRegistry clients_;

  // Started when a client first caps the camera's quality; last, so that its thread (which
  // publishes) is joined before anything it uses goes.
  std::once_flag requality_started_;
  std::unique_ptr<CameraRequality> requality_;
};

}  // namespace mobot::api
