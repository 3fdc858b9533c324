#include "api/stream_hub.h"

#include <algorithm>
#include <boost/asio/post.hpp>
#include <chrono>
#include <map>

#include "api/goal_json.h"
#include "api/prometheus_text.h"
#include "api/stream_session.h"
#include "api/wall_clock.h"
#include "api/websocket_frames.h"

namespace mobot::api {
namespace {

// The close code of a stream whose token stopped authenticating: 4000-4999 are the
// application's (RFC 6455 7.4.2), and 4401 reads as HTTP's 401.
constexpr std::uint16_t kTokenInactive = 4401;

std::shared_ptr<const std::string> as_text_frame(std::string payload) {
  return std::make_shared<const std::string>(encode_ws_frame(WsOpcode::kText, payload));
}

std::shared_ptr<const std::string> as_binary_frame(std::string payload) {
  return std::make_shared<const std::string>(encode_ws_frame(WsOpcode::kBinary, payload));
}

}  // namespace

StreamHub::StreamHub(StreamOptions options) : options_(options) {}

bool StreamHub::wanted(TopicId topic) const {
  const auto i = topic_index(topic);
  return json_subscribers_[i].load(std::memory_order_relaxed) > 0 ||
         binary_subscribers_[i].load(std::memory_order_relaxed) > 0;
}

FrameStamp StreamHub::next_stamp(TopicId topic, double t_s) {
  return {t_s, seq_[topic_index(topic)].fetch_add(1, std::memory_order_relaxed) + 1,
          wall_clock_us()};
}

void StreamHub::publish_json(TopicId topic, double t_s, const nlohmann::json& data) {
  const FrameStamp stamp = next_stamp(topic, t_s);
  SharedFrame frame;
  frame.wall_us = stamp.wall_us;
  frame.json = as_text_frame(encode_json_frame(topic_spec(topic).name, stamp, data));
  distribute(topic, frame);
}

void StreamHub::publish_pose(double t_s, const geometry::Pose2D& pose, const msgs::Twist& velocity,
                             const std::array<double, 9>& covariance,
                             std::optional<double> steering_rad) {
  if (!wanted(TopicId::kPose)) {
    next_stamp(TopicId::kPose, t_s);
    return;
  }
  nlohmann::json data{{"x", pose.x},
                      {"y", pose.y},
                      {"theta", pose.theta},
                      {"v", velocity.linear_mps},
                      {"w", velocity.angular_radps},
                      {"cov", covariance}};
  if (steering_rad) data["steering_rad"] = *steering_rad;
  publish_json(TopicId::kPose, t_s, std::move(data));
}

void StreamHub::publish_odom(const msgs::Odometry& odometry) {
  if (!wanted(TopicId::kOdom)) {
    next_stamp(TopicId::kOdom, odometry.stamp_s);
    return;
  }
  publish_json(TopicId::kOdom, odometry.stamp_s,
               {{"x", odometry.pose.x},
                {"y", odometry.pose.y},
                {"theta", odometry.pose.theta},
                {"v", odometry.twist.linear_mps},
                {"w", odometry.twist.angular_radps}});
}

template <class JsonData, class BinaryFrame>
SharedFrame StreamHub::encode_bulk(TopicId topic, const FrameStamp& stamp, JsonData&& json_data,
                                   BinaryFrame&& binary_frame) {
  const auto i = topic_index(topic);
  SharedFrame frame;
  frame.wall_us = stamp.wall_us;
  // Each encoding only when somebody subscribed to it.
  if (json_subscribers_[i].load(std::memory_order_relaxed) > 0) {
    frame.json = as_text_frame(encode_json_frame(topic_spec(topic).name, stamp, json_data()));
  }
  if (binary_subscribers_[i].load(std::memory_order_relaxed) > 0) {
    frame.binary = as_binary_frame(binary_frame(stamp));
  }
  return frame;
}

template <class JsonData, class BinaryFrame>
void StreamHub::publish_bulk(TopicId topic, double t_s, JsonData&& json_data,
                             BinaryFrame&& binary_frame) {
  const SharedFrame frame = encode_bulk(topic, next_stamp(topic, t_s), json_data, binary_frame);
  if (frame.json || frame.binary) distribute(topic, frame);
}

void StreamHub::publish_scan(const msgs::LaserScan& scan, const geometry::Pose2D& sensor_in_map) {
  publish_bulk(
      TopicId::kScan, scan.stamp_s, [&] { return scan_json(scan, sensor_in_map); },
      [&](const FrameStamp& stamp) { return encode_binary_scan(stamp, scan, sensor_in_map); });
}

SharedFrame StreamHub::encode_camera(const FrameStamp& stamp, const msgs::Image& image) {
  return encode_bulk(
      TopicId::kCamera, stamp, [&] { return camera_json(image); },
      [&](const FrameStamp& s) { return encode_binary_camera(s, image); });
}

void StreamHub::publish_camera(const msgs::Image& image) {
  const FrameStamp stamp = next_stamp(TopicId::kCamera, image.stamp_s);
  if (!wanted(TopicId::kCamera)) return;
  // A JPEG of unknown quality may still be compressed further.
  const int source_quality =
      image.encoding == "jpeg" ? (image.jpeg_quality > 0 ? image.jpeg_quality : 100) : 0;
  SharedFrame frame = encode_camera(stamp, image);
  frame.source_quality = source_quality;
  distribute(TopicId::kCamera, frame);
  std::vector<int> qualities = qualities_below(source_quality);
  if (qualities.empty()) return;
  std::call_once(requality_started_, [this] {
    requality_ = std::make_unique<CameraRequality>(
        [this](const FrameStamp& s, std::vector<std::pair<int, msgs::Image>> variants) {
          publish_requalified(s, std::move(variants));
        });
  });
  requality_->submit(image, stamp, std::move(qualities));
}

std::vector<int> StreamHub::qualities_below(int source_quality) const {
  std::vector<int> qualities;
  for (int quality = 1; quality < source_quality; ++quality) {
    if (camera_quality_subscribers_[static_cast<std::size_t>(quality)].load(
            std::memory_order_relaxed) > 0) {
      qualities.push_back(quality);
    }
  }
  return qualities;
}

void StreamHub::publish_requalified(const FrameStamp& stamp,
                                    std::vector<std::pair<int, msgs::Image>> variants) {
  for (const auto& [quality, image] : variants) {
    SharedFrame frame = encode_camera(stamp, image);
    frame.quality_variant = quality;
    if (frame.json || frame.binary) distribute(TopicId::kCamera, frame);
  }
  flush();
}

void StreamHub::publish_target(const TrackingSnapshot& snapshot) {
  if (!wanted(TopicId::kTarget)) {
    next_stamp(TopicId::kTarget, snapshot.t_s);
    return;
  }
  publish_json(TopicId::kTarget, snapshot.t_s, tracking_json(snapshot));
}

void StreamHub::publish_cloud(double t_s, const CloudChunk& chunk,
                              std::span<const perception::CloudPoint> points) {
  publish_bulk(
      TopicId::kCloud, t_s, [&] { return cloud_json(chunk, points); },
      [&](const FrameStamp& stamp) { return encode_binary_cloud(stamp, chunk, points); });
}

void StreamHub::publish_sonar(const msgs::SonarRing& ring, const geometry::Pose2D& base_in_map) {
  if (!wanted(TopicId::kSonar)) {
    next_stamp(TopicId::kSonar, ring.stamp_s);
    return;
  }
  publish_json(TopicId::kSonar, ring.stamp_s, range_ring_json(ring.readings, base_in_map));
}

void StreamHub::publish_ir(const msgs::IrRing& ring, const geometry::Pose2D& base_in_map) {
  if (!wanted(TopicId::kIr)) {
    next_stamp(TopicId::kIr, ring.stamp_s);
    return;
  }
  publish_json(TopicId::kIr, ring.stamp_s, range_ring_json(ring.readings, base_in_map));
}

void StreamHub::publish_costmap(double t_s, const planning::PlanningGrid& costmap, bool local) {
  publish_bulk(
      local ? TopicId::kLocalCostmap : TopicId::kCostmap, t_s,
      [&] { return costmap_json(costmap, local); },
      [&](const FrameStamp& stamp) { return encode_binary_costmap(stamp, costmap, local); });
}

void StreamHub::publish_particles(double t_s, std::span<const estimation::WeightedPose> particles,
                                  std::size_t total) {
  publish_bulk(
      TopicId::kParticles, t_s, [&] { return particles_json(particles, total); },
      [&](const FrameStamp& stamp) { return encode_binary_particles(stamp, particles, total); });
}

void StreamHub::publish_map_tiles(double t_s, std::shared_ptr<const mapping::OccupancyGrid> grid,
                                  const mapping::MapTileUpdate& tiles) {
  // A client that subscribes from now on gets the whole map so far; the ones that have the
  // earlier tiles get the changed ones.
  // (The whole map is stamped with the tile frame's number: a client may get both, harmlessly.)
  {
    const FrameStamp stamp{t_s, seq_[topic_index(TopicId::kMap)].load() + 1, wall_clock_us()};
    std::lock_guard lock(mutex_);
    LatestMap map{std::move(grid), 0, stamp, map_.generation + 1, {}};
    map.frame.wall_us = stamp.wall_us;
    map_ = std::move(map);
  }
  if (tiles.tiles.empty()) return;
  publish_bulk(
      TopicId::kMap, t_s, [&] { return map_tiles_json(tiles); },
      [&](const FrameStamp& stamp) { return encode_binary_map_tiles(stamp, tiles); });
}

void StreamHub::publish_map(double t_s, std::shared_ptr<const mapping::OccupancyGrid> grid,
                            std::int64_t map_id) {
  LatestMap map{std::move(grid), map_id, next_stamp(TopicId::kMap, t_s), 0, {}};
  map.frame.wall_us = map.stamp.wall_us;
  {
    std::lock_guard lock(mutex_);
    map.generation = map_.generation + 1;
    map_ = map;
  }
  // The map is current before the subscriber counts are read: a client counted here gets it in
  // the batch, one that subscribes later gets it from latest_map_frame().
  if (!wanted(TopicId::kMap)) return;
  const auto i = topic_index(TopicId::kMap);
  if (json_subscribers_[i].load() > 0) complete_map_frame(map, false);
  if (binary_subscribers_[i].load() > 0) complete_map_frame(map, true);
  if (map.frame.json || map.frame.binary) distribute(TopicId::kMap, map.frame);
}

SharedFrame StreamHub::latest_map_frame(bool binary) {
  LatestMap map;
  {
    std::lock_guard lock(mutex_);
    map = map_;
  }
  complete_map_frame(map, binary);
  return map.frame;
}

void StreamHub::complete_map_frame(LatestMap& map, bool binary) {
  auto& frame = binary ? map.frame.binary : map.frame.json;
  if (!map.grid || frame) return;
  // Encoded outside the lock: a large map takes long, and every publication of the control loop
  // takes this lock.
  frame = binary ? as_binary_frame(encode_binary_map(map.stamp, *map.grid, map.id))
                 : as_text_frame(encode_json_frame("map", map.stamp, map_json(*map.grid, map.id)));
  std::lock_guard lock(mutex_);
  // Kept for later subscribers while its map is current; of two threads that encoded it at the
  // same time, the first one's frame is shared.
  if (map_.generation != map.generation) return;
  auto& kept = binary ? map_.frame.binary : map_.frame.json;
  if (kept) {
    frame = kept;
  } else {
    kept = frame;
  }
}

void StreamHub::publish_status(const RobotSnapshot& snapshot) {
  if (!wanted(TopicId::kStatus)) {
    next_stamp(TopicId::kStatus, snapshot.t_s);
    return;
  }
  publish_json(TopicId::kStatus, snapshot.t_s, snapshot_json(snapshot));
}

void StreamHub::publish_event(double t_s, const std::string& kind, const nlohmann::json& detail) {
  if (!wanted(TopicId::kEvents)) {
    next_stamp(TopicId::kEvents, t_s);
    return;
  }
  publish_json(TopicId::kEvents, t_s, {{"t", t_s}, {"kind", kind}, {"detail", detail}});
}

void StreamHub::publish_goal(double t_s, const navigation::Goal& goal) {
  if (!wanted(TopicId::kGoal)) {
    next_stamp(TopicId::kGoal, t_s);
    return;
  }
  publish_json(TopicId::kGoal, t_s, goal_json(goal));
}

void StreamHub::publish_path(double t_s, const navigation::Goal& goal) {
  if (!wanted(TopicId::kPath)) {
    next_stamp(TopicId::kPath, t_s);
    return;
  }
  publish_json(TopicId::kPath, t_s, {{"goal_id", goal.id}, {"points", path_json(goal.path)}});
}

void StreamHub::publish_truth(const SimTruth& truth) {
  if (!wanted(TopicId::kTruth)) {
    next_stamp(TopicId::kTruth, truth.t_s);
    return;
  }
  nlohmann::json data{{"pose", pose_json(truth.pose)}, {"collisions", truth.collisions}};
  if (truth.steering_rad) data["steering_rad"] = *truth.steering_rad;
  publish_json(TopicId::kTruth, truth.t_s, std::move(data));
}

void StreamHub::distribute(TopicId topic, const SharedFrame& frame) {
  std::lock_guard lock(mutex_);
  if (sessions_->empty()) return;
  // Flushes stalled behind a long pass must not pile up: a session would keep only the newest
  // few frames of a topic anyway. (A camera frame compressed again for capped clients is a stream
  // of its own.)
  const auto same_topic = [topic, &frame](const TopicFrame& pending) {
    return pending.topic == topic && pending.frame.quality_variant == frame.quality_variant;
  };
  if (static_cast<std::size_t>(std::count_if(pending_.begin(), pending_.end(), same_topic)) >=
      options_.max_frames_per_topic) {
    pending_.erase(std::find_if(pending_.begin(), pending_.end(), same_topic));
    count_dropped();
  }
  pending_.push_back({topic, frame});
}

// A batch on its way to the sessions. The io threads that run it take sessions from `next` until
// none is left, so a thread busy elsewhere does not hold back the clients it would have written.
// Each pass starts one session further on (`first`): a client is written last once in as many
// passes as there are clients, not on every one, so every client sees the same latencies.
struct StreamHub::WritePass {
  FrameBatch frames;
  std::shared_ptr<const SessionList> sessions;
  std::size_t first = 0;
  std::atomic<std::size_t> next{0};
  std::atomic<unsigned> running{0};
};

void StreamHub::flush() {
  std::lock_guard lock(mutex_);
  if (pass_running_ || pending_.empty()) return;
  start_pass_locked();
}

void StreamHub::set_executor(boost::asio::any_io_executor executor, unsigned writers) {
  std::lock_guard lock(mutex_);
  executor_ = std::move(executor);
  writers_ = std::max(1U, writers);
}

void StreamHub::start_pass_locked() {
  if (!executor_ || sessions_->empty()) {
    pending_.clear();
    return;
  }
  const auto writers = static_cast<unsigned>(std::min<std::size_t>(sessions_->size(), writers_));
  auto pass = std::make_shared<WritePass>();
  pass->frames.swap(pending_);
  pending_.reserve(pass->frames.capacity());
  pass->sessions = sessions_;
  pass->first = passes_started_++ % sessions_->size();
  pass->running = writers;
  pass_running_ = true;
  for (unsigned i = 0; i < writers; ++i) {
    boost::asio::post(*executor_, [this, pass] {
      run_pass(*pass);
      if (pass->running.fetch_sub(1) == 1) finish_pass();
    });
  }
}

void StreamHub::run_pass(WritePass& pass) {
  const SessionList& sessions = *pass.sessions;
  for (std::size_t i = pass.next.fetch_add(1); i < sessions.size(); i = pass.next.fetch_add(1)) {
    sessions[(pass.first + i) % sessions.size()]->deliver(pass.frames);
  }
}

void StreamHub::finish_pass() {
  std::lock_guard lock(mutex_);
  pass_running_ = false;
  if (!pending_.empty()) start_pass_locked();
}

void StreamHub::attach(const std::shared_ptr<StreamSession>& session) {
  std::lock_guard lock(mutex_);
  auto sessions = std::make_shared<SessionList>(*sessions_);
  sessions->push_back(session);
  sessions_ = std::move(sessions);
  sessions_opened_.fetch_add(1, std::memory_order_relaxed);
}

void StreamHub::detach(const StreamSession* session) {
  std::lock_guard lock(mutex_);
  auto sessions = std::make_shared<SessionList>(*sessions_);
  std::erase_if(*sessions, [&](const auto& s) { return s.get() == session; });
  sessions_ = std::move(sessions);
}

void StreamHub::count_subscription(TopicId topic, bool binary, int delta) {
  auto& counter =
      binary ? binary_subscribers_[topic_index(topic)] : json_subscribers_[topic_index(topic)];
  counter.fetch_add(delta, std::memory_order_relaxed);
}

void StreamHub::count_camera_quality(int quality, int delta) {
  if (quality < 1 || quality > 100) return;
  camera_quality_subscribers_[static_cast<std::size_t>(quality)].fetch_add(
      delta, std::memory_order_relaxed);
}

std::string StreamHub::hello_frame() const {
  nlohmann::json topics = nlohmann::json::array();
  for (const auto& spec : kTopics) {
    if (spec.sim_only && !options_.simulated) continue;
    nlohmann::json encodings =
        spec.binary_id != 0 ? nlohmann::json{"json", "binary"} : nlohmann::json{"json"};
    topics.push_back({{"name", spec.name},
                      {"rate_hz", options_.nominal_rate_hz[topic_index(spec.id)]},
                      {"encodings", std::move(encodings)}});
  }
  const nlohmann::json hello{{"op", "hello"}, {"version", 1}, {"topics", std::move(topics)}};
  return hello.dump();
}

void StreamHub::close_all() {
  std::shared_ptr<const SessionList> sessions;
  {
    std::lock_guard lock(mutex_);
    sessions = sessions_;
  }
  for (const auto& session : *sessions) session->close(1001, "server shutting down");
}

void StreamHub::close_inactive_tokens(const std::function<bool(std::int64_t token_id)>& is_active) {
  std::shared_ptr<const SessionList> sessions;
  {
    std::lock_guard lock(mutex_);
    sessions = sessions_;
  }
  std::map<std::int64_t, bool> active;
  for (const auto& session : *sessions) {
    const std::int64_t token_id = session->token_id();
    auto known = active.find(token_id);
    if (known == active.end()) known = active.emplace(token_id, is_active(token_id)).first;
    if (!known->second) session->close(kTokenInactive, "token revoked or expired");
  }
}

void StreamHub::note_frame_age(TopicId topic, double age_s) {
  AgeHistogram& histogram = frame_ages_[topic_index(topic)];
  const double age = std::max(0.0, age_s);
  const auto bin = static_cast<std::size_t>(
      std::lower_bound(kAgeBounds_s.begin(), kAgeBounds_s.end(), age) - kAgeBounds_s.begin());
  histogram.in_bin[bin].fetch_add(1, std::memory_order_relaxed);
  histogram.sum_us.fetch_add(static_cast<std::uint64_t>(age * 1e6), std::memory_order_relaxed);
}

void StreamHub::append_frame_ages(std::string& out) const {
  append_family(out, "mobot_stream_frame_age_seconds", "histogram",
                "How old a frame was, since it was published, when a client's socket took it.");
  for (const TopicSpec& spec : kTopics) {
    const AgeHistogram& histogram = frame_ages_[topic_index(spec.id)];
    std::array<std::uint64_t, kAgeBounds_s.size() + 1> bins{};
    for (std::size_t i = 0; i < bins.size(); ++i) bins[i] = histogram.in_bin[i].load();
    std::uint64_t count = 0;
    for (const std::uint64_t in_bin : bins) count += in_bin;
    if (count == 0) continue;
    const std::string topic = "topic=\"" + std::string(spec.name) + "\"";
    std::uint64_t at_or_below = 0;
    for (std::size_t i = 0; i < kAgeBounds_s.size(); ++i) {
      at_or_below += bins[i];
      append_sample(out, "mobot_stream_frame_age_seconds_bucket", static_cast<double>(at_or_below),
                    topic + ",le=\"" + prometheus_number(kAgeBounds_s[i]) + "\"");
    }
    append_sample(out, "mobot_stream_frame_age_seconds_bucket", static_cast<double>(count),
                  topic + ",le=\"+Inf\"");
    append_sample(out, "mobot_stream_frame_age_seconds_sum",
                  static_cast<double>(histogram.sum_us.load()) * 1e-6, topic);
    append_sample(out, "mobot_stream_frame_age_seconds_count", static_cast<double>(count), topic);
  }
}

void StreamHub::count_sent(std::uint64_t frames, std::uint64_t bytes) {
  frames_sent_.fetch_add(frames, std::memory_order_relaxed);
  bytes_sent_.fetch_add(bytes, std::memory_order_relaxed);
}

std::string StreamHub::metrics_text() const {
  std::size_t clients = 0;
  {
    std::lock_guard lock(mutex_);
    clients = sessions_->size();
  }
  std::string out;
  append_metric(out, "mobot_stream_clients", "gauge", "WebSocket stream sessions open now.",
                static_cast<double>(clients));
  append_metric(out, "mobot_stream_sessions_total", "counter", "WebSocket stream sessions opened.",
                static_cast<double>(sessions_opened_.load()));
  append_metric(out, "mobot_stream_frames_sent_total", "counter",
                "Frames written to stream clients.", static_cast<double>(frames_sent_.load()));
  append_metric(out, "mobot_stream_bytes_sent_total", "counter", "Bytes written to stream clients.",
                static_cast<double>(bytes_sent_.load()));
  append_metric(out, "mobot_stream_frames_dropped_total", "counter",
                "Frames dropped for clients that read too slowly.",
                static_cast<double>(frames_dropped_.load()));
  append_metric(out, "mobot_stream_messages_rate_limited_total", "counter",
                "Client messages dropped for coming faster than the rate limit.",
                static_cast<double>(messages_rate_limited_.load()));
  append_metric(out, "mobot_stream_frames_thinned_total", "counter",
                "Frames left out for a client's max_kbps.",
                static_cast<double>(frames_thinned_.load()));
  append_frame_ages(out);
  out += clients_.metrics_text();
  return out;
}

}  // namespace mobot::api
