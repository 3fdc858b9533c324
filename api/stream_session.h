#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <nlohmann/json.hpp>

#include "api/byte_budget.h"
#include "api/ports/ports.h"
#include "api/rest_reply.h"
#include "api/stream_hub.h"
#include "api/stream_request.h"
#include "api/stream_topics.h"
#include "api/teleop_lease.h"
#include "api/token_bucket.h"
#include "api/websocket_frames.h"

namespace mobot::api {

// One WebSocket client of /api/v1/stream, after the HTTP upgrade. Reads client ops on its strand.
// Takes the hub's batches of frames on any io thread into small per-topic queues (dropping the
// oldest), and sends everything pending as one gathered write: first straight away on a
// non-blocking socket, by whichever thread has frames to send; only what the socket does not take
// at once goes on as an asynchronous write, from the strand. A client that falls silent is pinged
// every ping_interval_ms and, when nothing at all has come from it for idle_timeout_ms, closed
// with 1001 and released.
// Who is on the other end of a stream: the token it authenticated with and the connection.
struct StreamPeer {
  Caller caller;
  ClientContext client;
  ClientRegistry::Registration registration;  // the connection's entry in GET /api/v1/clients
};

class StreamSession : public std::enable_shared_from_this<StreamSession> {
 public:
  StreamSession(boost::asio::ip::tcp::socket socket, StreamHub& hub, const Ports& ports,
                StreamPeer peer, std::string already_received);
  ~StreamSession();

  void start();
  // Takes the frames of the topics this client subscribed to and writes them. Any thread.
  void deliver(const FrameBatch& frames);
  // Sends a close frame after everything queued, then releases the connection. Any thread.
  void close(std::uint16_t code, std::string reason);
  // The token the client authenticated with.
  std::int64_t token_id() const { return peer_.caller.token_id; }

 private:
  struct Subscription {
    bool active = false;
    bool binary = false;
    std::int64_t min_interval_us = 0;
    std::int64_t last_sent_wall_us = 0;
    int quality_cap = 0;  // camera: the JPEG quality this client takes at most (0: the camera's)
  };

  using Clock = std::chrono::steady_clock;

  void read_more();
  // Parses received bytes and handles the messages; false once the client broke the protocol
  // (the session is then closing with the parser's code).
  bool process_received(std::string_view bytes);
  bool checks_liveness() const;
  void watch_client();
  void check_client();
  Clock::time_point next_check() const;
  void handle_message(WsMessage message);
  void handle_text(const std::string& text);
  // Whether a message may be handled at the client's rate; counts and reports one that may not.
  bool within_rate(const WsMessage& message);
  // Queues the close frame after what is queued already; nothing is sent after it.
  void queue_close(std::string frame);
  bool is_closing();
  // The parsed client ops (api/stream_request.h), carried out.
  void carry_out(const SubscribeRequest& request);
  void carry_out(const UnsubscribeRequest& request);
  void carry_out(const StreamTeleopRequest& request);
  void carry_out(const PingRequest& request);
  void carry_out(const EstopRequest& request);
  void reply_teleop(const Result<msgs::Twist>& result, const StreamTeleopRequest& request);
  // On the strand, once the robot took a teleop: the drive's lease and its audit.
  void note_drive(const msgs::Twist& applied, int ttl_ms);
  // At the lease's end with no command after it: the drive ended, because the link stalled
  // (nothing at all heard since the command) or the operator stopped sending.
  void check_lease(Clock::time_point now);
  // A ping whose payload is the time it was sent, answered by a pong that gives the round trip.
  void ping_for_round_trip(Clock::time_point now);
  void on_pong(std::string_view payload);
  Clock::duration round_trip_ping_interval() const;
  Claimant claimant() const;
  // The subscribed topics, for GET /api/v1/clients.
  void note_topics();
  // A write of all of in_flight_ is done: `frames` frames, `bytes` bytes.
  void count_sent(std::size_t frames, std::size_t bytes);
  void reply(const nlohmann::json& message);
  // `identity`: which message it answers (request_identity), when that is known.
  void reply_error(const std::string& code, const std::string& message,
                   const nlohmann::json& identity = nlohmann::json::object());
  void queue_control(std::shared_ptr<const std::string> frame);
  void take_locked(TopicId topic, const SharedFrame& frame);
  // Ends a subscription's share in the hub's counts (the caller clears or replaces it).
  void release_locked(TopicId topic, const Subscription& subscription);
  void write_pending();
  void write_locked(std::unique_lock<std::mutex>& lock);
  bool gather_locked();
  void write_rest(std::size_t written);
  void on_written(boost::system::error_code error, std::size_t bytes);
  void shut_down();
  void close_socket();

  boost::asio::ip::tcp::socket socket_;
  StreamHub& hub_;
  Ports ports_;
  StreamPeer peer_;
  WsFrameParser parser_;
  std::array<char, 8192> read_buffer_{};
  std::string already_received_;

  // The client's liveness, on the strand: when it last sent anything, when it was last pinged.
  boost::asio::steady_timer timer_;
  Clock::time_point last_heard_;
  Clock::time_point last_ping_;
  bool idle_closed_ = false;  // closed for silence: released at the next check if still open
  Clock::time_point last_round_trip_ping_;
  TokenBucket message_budget_;
  Clock::time_point last_rate_notice_{};
  bool over_rate_ = false;  // the message being handled came over the rate: only an e-stop goes

  // The client's teleop lease, on the strand.
  std::optional<std::uint64_t> last_seq_;
  TeleopLease lease_;
  bool watching_lease_ = false;  // a drive's lease runs: its end is checked

  std::mutex mutex_;  // guards the subscription and outgoing state below
  std::array<Subscription, kTopicCount> subscriptions_{};
  // A topic frame waiting for the socket, with when it was published: how old it is when the
  // socket takes it (mobot_stream_frame_age_seconds).
  struct QueuedFrame {
    std::shared_ptr<const std::string> bytes;
    std::int64_t wall_us = 0;
  };
  // A few frames each (max_frames_per_topic): vectors keep their storage from tick to tick.
  std::array<std::vector<QueuedFrame>, kTopicCount> topic_queues_{};
  std::deque<std::shared_ptr<const std::string>> control_queue_;
  ByteBudget budget_;  // the client's max_kbps
  // Owned by whoever set writing_: the frames being written and their buffers.
  std::vector<std::shared_ptr<const std::string>> in_flight_;
  std::vector<std::pair<TopicId, std::int64_t>> in_flight_stamps_;  // the topic frames' wall_us
  std::vector<boost::asio::const_buffer> buffers_;
  std::size_t in_flight_bytes_ = 0;
  bool writing_ = false;         // a write (synchronous or asynchronous) owns in_flight_
  bool in_syscall_ = false;      // a thread is inside write_some: the socket must not close now
  bool close_deferred_ = false;  // close_socket() waits for that write_some to return
  bool closing_ = false;         // a close frame is queued: send nothing after it
  bool closed_ = false;          // shut down: write nothing more, the socket closes
  bool socket_closed_ = false;
};

}  // namespace mobot::api
