#include "api/stream_session.h"

#include <algorithm>
#include <boost/asio/post.hpp>
#include <boost/asio/write.hpp>
#include <cmath>
#include <variant>

#include "api/api_error.h"
#include "api/teleop_audit.h"
#include "api/wall_clock.h"

namespace mobot::api {
namespace {

// Frames of a thinned topic are taken when at least this share of the interval has passed, so a
// 10 Hz request on a 50 Hz topic does not alias down to 8.3 Hz through timing jitter.
constexpr double kRateTolerance = 0.8;

// RFC 6455 7.4.1: the endpoint is going away, here because its peer has gone silent.
constexpr std::uint16_t kGoingAway = 1001;

// The lease of the standing command that stops a drive whose stream closed: the shortest teleop.
constexpr int kStoppingTtl_ms = 50;

// Over its rate a client's messages are dropped unread, except texts this short, which are parsed
// in case they are an e-stop (`{"op":"estop","engaged":true}` and spaces).
constexpr std::size_t kLargestEstopBytes = 256;

// A client that capped the camera's quality takes the copy made at its cap, or the camera's own
// frame when that is not above the cap (or cannot be made smaller); the others take the camera's.
bool serves_quality(int cap, const SharedFrame& frame) {
  if (frame.quality_variant != 0) return frame.quality_variant == cap;
  return cap == 0 || frame.source_quality <= cap;
}

}  // namespace

StreamSession::StreamSession(boost::asio::ip::tcp::socket socket, StreamHub& hub,
                             const Ports& ports, StreamPeer peer, std::string already_received)
    : socket_(std::move(socket)),
      hub_(hub),
      ports_(ports),
      peer_(std::move(peer)),
      parser_(hub.options().max_client_message_bytes),
      already_received_(std::move(already_received)),
      timer_(socket_.get_executor()),
      last_heard_(Clock::now()),
      last_ping_(last_heard_),
      last_round_trip_ping_(last_heard_),
      message_budget_(hub.options().client_messages_per_s, hub.options().client_message_burst) {}

StreamSession::~StreamSession() {
  for (std::size_t i = 0; i < kTopicCount; ++i) {
    if (subscriptions_[i].active) release_locked(static_cast<TopicId>(i), subscriptions_[i]);
  }
}

void StreamSession::release_locked(TopicId topic, const Subscription& subscription) {
  hub_.count_subscription(topic, subscription.binary, -1);
  if (subscription.quality_cap > 0) hub_.count_camera_quality(subscription.quality_cap, -1);
}

void StreamSession::start() {
  boost::system::error_code ignored;
  socket_.set_option(boost::asio::ip::tcp::no_delay(true), ignored);
  socket_.set_option(boost::asio::socket_base::keep_alive(true), ignored);
  // Whichever io thread has frames for this client writes them at once, and a full socket buffer
  // must make that write return, not wait. Both flags are set now, before the hub and the strand
  // share the socket, so that no later operation changes its state.
  socket_.non_blocking(true, ignored);
  socket_.native_non_blocking(true, ignored);
  hub_.attach(shared_from_this());
  boost::asio::post(socket_.get_executor(), [self = shared_from_this()] {
    self->queue_control(std::make_shared<const std::string>(
        encode_ws_frame(WsOpcode::kText, self->hub_.hello_frame())));
    // Frames the client sent right behind its upgrade request came with it.
    const std::string early = std::move(self->already_received_);
    self->already_received_.clear();
    if (!self->process_received(early)) return;
    self->read_more();
    self->watch_client();
  });
}

void StreamSession::deliver(const FrameBatch& frames) {
  std::unique_lock lock(mutex_);
  if (closing_) return;
  for (const auto& [topic, frame] : frames) take_locked(topic, frame);
  write_locked(lock);
}

void StreamSession::take_locked(TopicId topic, const SharedFrame& frame) {
  const auto i = topic_index(topic);
  Subscription& subscription = subscriptions_[i];
  if (!subscription.active) return;
  const auto& bytes = subscription.binary && frame.binary ? frame.binary : frame.json;
  if (!bytes || !serves_quality(subscription.quality_cap, frame)) return;
  if (subscription.min_interval_us > 0 &&
      frame.wall_us - subscription.last_sent_wall_us <
          static_cast<std::int64_t>(kRateTolerance * subscription.min_interval_us)) {
    return;
  }
  // Under a byte-rate cap the sampled sensor and bulk topics thin out; the state and whatever
  // loses information when skipped (map tiles, cloud chunks, events) always go, charged.
  const TopicSpec& spec = topic_spec(topic);
  if (!budget_.take(bytes->size(), spec.sampled ? spec.priority : TopicPriority::kState,
                    ByteBudget::Clock::now())) {
    hub_.count_thinned();
    return;
  }
  subscription.last_sent_wall_us = frame.wall_us;
  auto& queue = topic_queues_[i];
  if (queue.size() >= hub_.options().max_frames_per_topic) {
    queue.erase(queue.begin());
    hub_.count_dropped();
    if (ClientRecord* record = peer_.registration.record().get()) record->add_dropped();
  }
  queue.push_back({bytes, frame.wall_us});
}

void StreamSession::close(std::uint16_t code, std::string reason) {
  queue_close(encode_ws_close(code, reason));
}

void StreamSession::queue_close(std::string frame) {
  {
    std::lock_guard lock(mutex_);
    if (closing_) return;
    // Nothing may follow the close frame, and queued data frames would otherwise go after it.
    for (auto& queue : topic_queues_) queue.clear();
    control_queue_.push_back(std::make_shared<const std::string>(std::move(frame)));
    closing_ = true;
  }
  // Once it is written, write_locked() shuts the session down, which closes the TCP connection.
  write_pending();
}

bool StreamSession::is_closing() {
  std::lock_guard lock(mutex_);
  return closing_;
}

void StreamSession::read_more() {
  socket_.async_read_some(
      boost::asio::buffer(read_buffer_),
      [self = shared_from_this()](boost::system::error_code error, std::size_t bytes) {
        if (error) {
          self->shut_down();
          return;
        }
        // Any bytes count, a pong or part of a long message alike: the client is there.
        self->last_heard_ = Clock::now();
        if (!self->process_received({self->read_buffer_.data(), bytes})) return;
        // Reading goes on after a close frame (the parser ignores what follows it) so that a
        // client that drops the connection before the reply is out releases the session.
        self->read_more();
      });
}

bool StreamSession::process_received(std::string_view bytes) {
  parser_.feed(bytes);
  while (auto message = parser_.next()) handle_message(std::move(*message));
  if (parser_.failed()) {
    // RFC 6455 7.1.7: fail the connection with the violation's code, reading nothing more.
    close(parser_.error_code(), parser_.error_message());
    return false;
  }
  return true;
}

bool StreamSession::checks_liveness() const {
  return hub_.options().ping_interval_ms > 0 && hub_.options().idle_timeout_ms > 0;
}

void StreamSession::watch_client() {
  const Clock::time_point next = next_check();
  if (next == Clock::time_point::max()) return;
  timer_.expires_at(next);
  timer_.async_wait([self = shared_from_this()](boost::system::error_code error) {
    if (!error) self->check_client();
  });
}

StreamSession::Clock::time_point StreamSession::next_check() const {
  Clock::time_point next = Clock::time_point::max();
  if (checks_liveness()) {
    const std::chrono::milliseconds ping_interval(hub_.options().ping_interval_ms);
    const std::chrono::milliseconds idle_timeout(hub_.options().idle_timeout_ms);
    next = idle_closed_ ? Clock::now() + ping_interval
                        : std::min(last_heard_ + idle_timeout,
                                   std::max(last_heard_, last_ping_) + ping_interval);
  }
  const Clock::duration round_trip = round_trip_ping_interval();
  if (round_trip > Clock::duration::zero())
    next = std::min(next, last_round_trip_ping_ + round_trip);
  if (watching_lease_) next = std::min(next, lease_.until());
  return next;
}

void StreamSession::check_client() {
  {
    std::lock_guard lock(mutex_);
    if (closed_) return;
  }
  const auto now = Clock::now();
  if (watching_lease_ && now >= lease_.until()) check_lease(now);
  if (checks_liveness()) {
    if (idle_closed_) {
      // The close frame did not get out: a client that neither reads nor writes is let go anyway.
      shut_down();
      return;
    }
    if (now - last_heard_ >= std::chrono::milliseconds(hub_.options().idle_timeout_ms)) {
      idle_closed_ = true;
      close(kGoingAway, "idle timeout");
    } else if (now - std::max(last_heard_, last_ping_) >=
               std::chrono::milliseconds(hub_.options().ping_interval_ms)) {
      // RFC 6455 5.5.2: a client answers a ping with a pong, so a client that is there is heard.
      last_ping_ = now;
      queue_control(std::make_shared<const std::string>(encode_ws_frame(WsOpcode::kPing, "")));
    }
  }
  const Clock::duration round_trip = round_trip_ping_interval();
  if (!idle_closed_ && round_trip > Clock::duration::zero() &&
      now - last_round_trip_ping_ >= round_trip) {
    ping_for_round_trip(now);
  }
  watch_client();
}

StreamSession::Clock::duration StreamSession::round_trip_ping_interval() const {
  Clock::duration interval = std::chrono::milliseconds(hub_.options().round_trip_ping_interval_ms);
  if (watching_lease_) {
    const Clock::duration half_ttl = (lease_.until() - lease_.last_command()) / 2;
    if (interval <= Clock::duration::zero() || half_ttl < interval) interval = half_ttl;
  }
  return interval;
}

void StreamSession::ping_for_round_trip(Clock::time_point now) {
  last_round_trip_ping_ = now;
  last_ping_ = now;
  const auto sent_us = static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::microseconds>(now.time_since_epoch()).count());
  std::string payload(8, '\0');
  for (int i = 0; i < 8; ++i)
    payload[static_cast<std::size_t>(i)] = static_cast<char>(sent_us >> (56 - 8 * i));
  queue_control(std::make_shared<const std::string>(encode_ws_frame(WsOpcode::kPing, payload)));
}

void StreamSession::on_pong(std::string_view payload) {
  // Only the answer to one of our round-trip pings carries 8 bytes; RFC 6455 5.5.3 lets a client
  // send pongs of its own, which tell nothing.
  if (payload.size() != 8) return;
  std::uint64_t sent_us = 0;
  for (const char byte : payload) sent_us = (sent_us << 8) | static_cast<unsigned char>(byte);
  const auto now_us = static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::microseconds>(Clock::now().time_since_epoch())
          .count());
  if (sent_us > now_us || now_us - sent_us > 60'000'000) return;
  if (ClientRecord* record = peer_.registration.record().get()) {
    record->set_rtt_ms(static_cast<double>(now_us - sent_us) / 1000.0);
  }
}

bool StreamSession::within_rate(const WsMessage& message) {
  const auto now = Clock::now();
  over_rate_ = !message_budget_.take(now);
  if (!over_rate_) return true;
  hub_.count_rate_limited();
  if (now - last_rate_notice_ >= std::chrono::seconds(1)) {
    last_rate_notice_ = now;
    reply_error("rate_limited",
                "more than " +
                    std::to_string(static_cast<int>(hub_.options().client_messages_per_s)) +
                    " messages a second: messages are dropped");
  }
  // A short text may be an e-stop, which goes whatever the rate; anything else is dropped unread.
  return message.opcode == WsOpcode::kText && message.payload.size() <= kLargestEstopBytes;
}

void StreamSession::handle_message(WsMessage message) {
  const bool counted = message.opcode == WsOpcode::kText || message.opcode == WsOpcode::kBinary ||
                       message.opcode == WsOpcode::kPing;
  over_rate_ = false;
  if (counted && !within_rate(message)) return;
  if (over_rate_ && message.opcode == WsOpcode::kPing) return;
  switch (message.opcode) {
    case WsOpcode::kPing:
      queue_control(
          std::make_shared<const std::string>(encode_ws_frame(WsOpcode::kPong, message.payload)));
      return;
    case WsOpcode::kPong:
      on_pong(message.payload);
      return;
    case WsOpcode::kClose:
      // RFC 6455 5.5.1: answered with a close frame echoing the client's status code; the TCP
      // connection closes once it is written (7.1.1).
      queue_close(encode_ws_close_reply(message.payload));
      return;
    default:
      break;
  }
  // A request the session could no longer answer is not carried out either: a teleop arriving
  // after the server's close frame must not move the robot unacknowledged.
  if (is_closing()) return;
  if (message.opcode == WsOpcode::kBinary) {
    reply_error("unsupported_message", "client messages must be JSON text frames");
    return;
  }
  handle_text(message.payload);
}

void StreamSession::handle_text(const std::string& text) {
  nlohmann::json identity = nlohmann::json::object();
  try {
    const StreamMessage message = read_stream_message(text);
    identity = request_identity(message);
    StreamRequest request = parse_stream_request(message, peer_.caller.role);
    if (over_rate_ && !std::holds_alternative<EstopRequest>(request)) return;
    std::visit([this](const auto& parsed) { carry_out(parsed); }, request);
  } catch (const ApiError& error) {
    if (!over_rate_) reply_error(error.code(), error.what(), identity);
  } catch (const DomainException& error) {
    if (!over_rate_) reply_error(error.error().code, error.error().message, identity);
  }
}

void StreamSession::carry_out(const PingRequest& request) {
  reply({{"op", "pong"},
         {"t", ports_.control.time_s()},
         {"wall_us", wall_clock_us()},
         {"id", request.id}});
}

void StreamSession::carry_out(const SubscribeRequest& request) {
  nlohmann::json accepted = nlohmann::json::array();
  std::vector<std::string> unknown;
  bool wants_map = false;
  for (const auto& name : request.topics) {
    const auto topic = topic_from_name(name);
    if (!topic || (topic_spec(*topic).sim_only && ports_.sim == nullptr)) {
      unknown.push_back(name);
      continue;
    }
    const bool topic_binary = request.binary && topic_spec(*topic).binary_id != 0;
    {
      std::lock_guard lock(mutex_);
      Subscription& subscription = subscriptions_[topic_index(*topic)];
      if (subscription.active) release_locked(*topic, subscription);
      const int quality_cap = *topic == TopicId::kCamera ? request.camera_quality : 0;
      subscription = {true, topic_binary, topic_spec(*topic).sampled ? request.min_interval_us : 0,
                      0, quality_cap};
      hub_.count_subscription(*topic, topic_binary, +1);
      if (quality_cap > 0) hub_.count_camera_quality(quality_cap, +1);
    }
    wants_map = wants_map || *topic == TopicId::kMap;
    accepted.push_back(name);
  }
  if (request.max_kbps) {
    std::lock_guard lock(mutex_);
    budget_.set_rate(*request.max_kbps * 1000.0 / 8.0, ByteBudget::Clock::now());
  }
  note_topics();
  // A subscribe that names no topic (one that only changes `max_kbps`) is acknowledged too.
  if (!accepted.empty() || unknown.empty()) reply({{"op", "subscribed"}, {"topics", accepted}});
  if (!unknown.empty()) {
    std::string list;
    for (const auto& name : unknown) list += (list.empty() ? "" : ", ") + name;
    reply_error("unknown_topic", "unknown topic(s): " + list, request_identity("subscribe"));
  }
  if (wants_map) {
    bool map_binary = false;
    {
      std::lock_guard lock(mutex_);
      map_binary = subscriptions_[topic_index(TopicId::kMap)].binary;
    }
    const SharedFrame map = hub_.latest_map_frame(map_binary);
    if (map.json || map.binary) {
      queue_control(map_binary ? map.binary : map.json);
    }
  }
}

void StreamSession::carry_out(const UnsubscribeRequest& request) {
  nlohmann::json removed = nlohmann::json::array();
  for (const auto& name : request.topics) {
    const auto topic = topic_from_name(name);
    if (!topic) continue;
    std::lock_guard lock(mutex_);
    Subscription& subscription = subscriptions_[topic_index(*topic)];
    if (!subscription.active) continue;
    release_locked(*topic, subscription);
    subscription = {};
    topic_queues_[topic_index(*topic)].clear();
    removed.push_back(name);
  }
  note_topics();
  reply({{"op", "unsubscribed"}, {"topics", removed}});
}

void StreamSession::note_topics() {
  ClientRecord* record = peer_.registration.record().get();
  if (record == nullptr) return;
  std::vector<std::string> names;
  {
    std::lock_guard lock(mutex_);
    for (const auto& spec : kTopics) {
      if (subscriptions_[topic_index(spec.id)].active) names.emplace_back(spec.name);
    }
  }
  record->set_topics(std::move(names));
}

void StreamSession::count_sent(std::size_t frames, std::size_t bytes) {
  hub_.count_sent(frames, bytes);
  if (!in_flight_stamps_.empty()) {
    const std::int64_t now_us = wall_clock_us();
    for (const auto& [topic, wall_us] : in_flight_stamps_) {
      hub_.note_frame_age(topic, static_cast<double>(now_us - wall_us) * 1e-6);
    }
  }
  if (ClientRecord* record = peer_.registration.record().get()) record->add_sent(bytes);
}

Claimant StreamSession::claimant() const {
  return Claimant{peer_.caller, peer_.client.id, true, peer_.client.address};
}

void StreamSession::carry_out(const StreamTeleopRequest& request) {
  if (request.seq) {
    // A command that is not the connection's newest (a client's retry, a replay) is dropped.
    if (last_seq_ && *request.seq <= *last_seq_) {
      throw ApiError(409, "stale_seq",
                     "seq " + std::to_string(*request.seq) + " is not above the last one (" +
                         std::to_string(*last_seq_) + "): the command is dropped");
    }
    last_seq_ = request.seq;
  }
  auto claimed = hub_.operator_lock().claim(claimant(), OperatorLock::Clock::now(), unix_now_s());
  if (!claimed.ok()) throw DomainException(claimed.error());
  // The command completes on the control loop. The reply is written from the strand, not from the
  // control loop's thread, and only while the session lives: a closed session is not kept for it.
  // A command the robot refuses leaves the operator lock as it was, session or not.
  ports_.control.teleop(
      request.command.twist, request.command.ttl_ms,
      [weak = weak_from_this(), lock = &hub_.operator_lock(), change = std::move(claimed.value()),
       request](Result<msgs::Twist> result) {
        if (!result.ok()) lock->undo(change);
        const auto self = weak.lock();
        if (!self) return;
        try {
          boost::asio::post(self->socket_.get_executor(),
                            [self, result = std::move(result), request] {
                              if (result.ok()) {
                                self->note_drive(result.value(), request.command.ttl_ms);
                              }
                              self->reply_teleop(result, request);
                            });
        } catch (...) {
          // Out of memory: the reply is lost, the control loop is not.
        }
      });
}

void StreamSession::reply_teleop(const Result<msgs::Twist>& result,
                                 const StreamTeleopRequest& request) {
  if (!result.ok()) {
    reply_error(result.error().code, result.error().message,
                request_identity("teleop", request.seq));
    return;
  }
  const msgs::Twist& applied = result.value();
  nlohmann::json message{{"op", "teleop"}, {"v", applied.linear_mps}, {"w", applied.angular_radps}};
  if (request.seq) message["seq"] = *request.seq;
  if (request.sent_ms) message["sent_ms"] = *request.sent_ms;
  reply(message);
}

void StreamSession::note_drive(const msgs::Twist& applied, int ttl_ms) {
  const TeleopLease::Change change = lease_.note(applied, ttl_ms, Clock::now());
  audit_drive_change(ports_.audit, claimant(), change);
  watching_lease_ = lease_.driving();
  if (watching_lease_) watch_client();
}

void StreamSession::check_lease(Clock::time_point now) {
  watching_lease_ = false;
  if (!lease_.driving() || lease_.running(now)) return;
  // The control loop stopped the robot when the lease lapsed; the trail says why it lapsed.
  audit_drive_end(ports_.audit, claimant(),
                  last_heard_ <= lease_.last_command() ? "link_stalled" : "lease_lapsed");
}

void StreamSession::carry_out(const EstopRequest& request) {
  // Carried out as it is read, never behind the lock, and its reply goes ahead of every frame
  // queued for this client; like REST's, it is acknowledged once it is in the run's audit trail.
  ports_.control.set_estop(
      request.engaged, [weak = weak_from_this(), audit = &ports_.audit, who = claimant(),
                        engaged = request.engaged](Result<bool> result) {
        if (!result.ok()) {
          if (const auto refused = weak.lock()) {
            boost::asio::post(refused->socket_.get_executor(), [refused, error = result.error()] {
              refused->reply_error(error.code, error.message, request_identity("estop"));
            });
          }
          return;
        }
        CommandRecord record = command_record(who, "estop");
        record.request_json = nlohmann::json{{"engaged", engaged}}.dump();
        audit->record_command(std::move(record), [weak, state = result.value()](Result<Done>) {
          const auto self = weak.lock();
          if (!self) return;
          boost::asio::post(self->socket_.get_executor(), [self, state] {
            self->reply({{"op", "estop"}, {"engaged", state}});
          });
        });
      });
}

void StreamSession::reply(const nlohmann::json& message) {
  queue_control(std::make_shared<const std::string>(encode_ws_frame(
      WsOpcode::kText, message.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace))));
}

void StreamSession::reply_error(const std::string& code, const std::string& message,
                                const nlohmann::json& identity) {
  nlohmann::json error{{"op", "error"}, {"code", code}, {"message", message}};
  error.update(identity);
  reply(error);
}

void StreamSession::queue_control(std::shared_ptr<const std::string> frame) {
  bool overflow = false;
  {
    std::lock_guard lock(mutex_);
    if (closing_ || closed_) return;
    overflow = control_queue_.size() >= hub_.options().max_control_frames;
    if (!overflow) control_queue_.push_back(std::move(frame));
  }
  if (overflow) {
    // A client that keeps sending requests but never reads the replies.
    shut_down();
    return;
  }
  write_pending();
}

bool StreamSession::gather_locked() {
  in_flight_bytes_ = 0;
  for (auto& frame : control_queue_) in_flight_.push_back(std::move(frame));
  control_queue_.clear();
  // The state first, then the sensors, then the bulk: on a thin link the pose is not stuck
  // behind a camera frame in the socket's buffer.
  for (std::size_t priority = 0; priority < kPriorityCount; ++priority) {
    for (const TopicSpec& spec : kTopics) {
      if (static_cast<std::size_t>(spec.priority) != priority) continue;
      auto& queue = topic_queues_[topic_index(spec.id)];
      for (auto& frame : queue) {
        in_flight_.push_back(std::move(frame.bytes));
        in_flight_stamps_.emplace_back(spec.id, frame.wall_us);
      }
      queue.clear();
    }
  }
  buffers_.clear();
  for (const auto& frame : in_flight_) {
    buffers_.emplace_back(frame->data(), frame->size());
    in_flight_bytes_ += frame->size();
  }
  return !in_flight_.empty();
}

void StreamSession::write_pending() {
  std::unique_lock lock(mutex_);
  write_locked(lock);
}

void StreamSession::write_locked(std::unique_lock<std::mutex>& lock) {
  // Frames queued while a write was on its way are sent by that writer when it is done.
  while (!writing_ && !closed_) {
    if (!gather_locked()) {
      if (!closing_) return;
      // Everything up to the close frame is written: release the socket and leave the hub, or the
      // session (and its file descriptor) would live on after the client has gone.
      lock.unlock();
      shut_down();
      return;
    }
    writing_ = true;
    in_syscall_ = true;
    lock.unlock();
    // The gathered write, straight away: most of the time the socket takes all of it, with no
    // reactor round trip and no completion handler.
    boost::system::error_code error;
    const std::size_t written = socket_.write_some(buffers_, error);
    lock.lock();
    in_syscall_ = false;
    if (close_deferred_) {
      close_deferred_ = false;
      boost::asio::post(socket_.get_executor(),
                        [self = shared_from_this()] { self->close_socket(); });
    }
    if (error && error != boost::asio::error::would_block &&
        error != boost::asio::error::try_again) {
      writing_ = false;
      in_flight_.clear();
      in_flight_stamps_.clear();
      lock.unlock();
      shut_down();
      return;
    }
    if (written < in_flight_bytes_) {
      // The client is behind: the rest goes asynchronously from the strand, and the frames that
      // arrive meanwhile wait in the bounded per-topic queues.
      lock.unlock();
      boost::asio::post(socket_.get_executor(),
                        [self = shared_from_this(), written] { self->write_rest(written); });
      return;
    }
    count_sent(in_flight_.size(), written);
    writing_ = false;
    in_flight_.clear();
    in_flight_stamps_.clear();
  }
}

void StreamSession::write_rest(std::size_t written) {
  std::size_t skip = written;
  auto first = buffers_.begin();
  while (skip >= first->size()) {
    skip -= first->size();
    ++first;
  }
  *first += skip;
  buffers_.erase(buffers_.begin(), first);
  boost::asio::async_write(
      socket_, buffers_,
      [self = shared_from_this(), written](boost::system::error_code error, std::size_t bytes) {
        self->on_written(error, written + bytes);
      });
}

void StreamSession::on_written(boost::system::error_code error, std::size_t bytes) {
  if (!error) count_sent(in_flight_.size(), bytes);
  {
    std::lock_guard lock(mutex_);
    writing_ = false;
    in_flight_.clear();
    in_flight_stamps_.clear();
  }
  if (error) {
    shut_down();
    return;
  }
  write_pending();
}

void StreamSession::shut_down() {
  {
    std::lock_guard lock(mutex_);
    if (closed_) return;
    closed_ = true;
    closing_ = true;
    for (auto& queue : topic_queues_) queue.clear();
    control_queue_.clear();
  }
  hub_.detach(this);
  // A lock held through this stream lapses with it: its operator is gone.
  hub_.operator_lock().connection_closed(peer_.client.id);
  // The socket closes on the strand, where its reads are started, and never under a write_some
  // of another thread (the descriptor could be reused by then).
  boost::asio::post(socket_.get_executor(), [self = shared_from_this()] { self->close_socket(); });
}

void StreamSession::close_socket() {
  {
    std::lock_guard lock(mutex_);
    if (socket_closed_) return;
    if (in_syscall_) {
      close_deferred_ = true;
      return;
    }
    socket_closed_ = true;
  }
  // A drive whose stream is gone stops now, not when its lease lapses: its operator is gone.
  if (watching_lease_ && lease_.running(Clock::now())) {
    ports_.control.teleop({}, kStoppingTtl_ms, [](Result<msgs::Twist>) {});
    audit_drive_end(ports_.audit, claimant(), "stream_closed");
  }
  watching_lease_ = false;
  // The liveness check holds the session: without it, the session is released.
  timer_.cancel();
  boost::system::error_code ignored;
  socket_.shutdown(boost::asio::ip::tcp::socket::shutdown_both, ignored);
  socket_.close(ignored);
}

}  // namespace mobot::api
