#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <boost/asio/ip/tcp.hpp>
#include <nlohmann/json.hpp>

#include "api/robot_port.h"
#include "api/stream_hub.h"
#include "api/stream_topics.h"
#include "api/websocket_frames.h"

namespace mobot::api {

// One WebSocket client of /api/v1/stream, after the HTTP upgrade. Reads client ops on its strand;
// takes frames from the hub on any thread into small per-topic queues (dropping the oldest), and
// sends everything pending as one gathered write.
class StreamSession : public std::enable_shared_from_this<StreamSession> {
 public:
  StreamSession(boost::asio::ip::tcp::socket socket, StreamHub& hub, RobotPort& port, Role role,
                std::string already_received);
  ~StreamSession();

  void start();
  // Queues the frame if this client subscribed to the topic. True when the caller must wake()
  // the session once its batch of publications is done.
  bool offer(TopicId topic, const SharedFrame& frame);
  void wake();
  void close(std::uint16_t code, std::string reason);

 private:
  struct Subscription {
    bool active = false;
    bool binary = false;
    std::int64_t min_interval_us = 0;
    std::int64_t last_sent_wall_us = 0;
  };

  void read_more();
  void handle_message(WsMessage message);
  void handle_op(const nlohmann::json& request);
  void subscribe(const nlohmann::json& request);
  void unsubscribe(const nlohmann::json& request);
  void teleop(const nlohmann::json& request);
  void reply(const nlohmann::json& message);
  void reply_error(const std::string& code, const std::string& message);
  void queue_control(std::shared_ptr<const std::string> frame);
  void write_pending();
  void on_written(boost::system::error_code error);
  void shut_down();
  std::vector<std::string> topic_names(const nlohmann::json& request, const char* op);

  boost::asio::ip::tcp::socket socket_;
  StreamHub& hub_;
  RobotPort& port_;
  Role role_;
  WsFrameParser parser_;
  std::array<char, 8192> read_buffer_{};
  std::string already_received_;

  std::mutex mutex_;  // guards the subscription and outgoing state below
  std::array<Subscription, kTopicCount> subscriptions_{};
  std::array<std::deque<std::shared_ptr<const std::string>>, kTopicCount> topic_queues_{};
  std::deque<std::shared_ptr<const std::string>> control_queue_;
  std::vector<std::shared_ptr<const std::string>> in_flight_;
  bool writing_ = false;
  bool wake_pending_ = false;
  bool closing_ = false;  // a close frame is queued: send nothing after it
  bool closed_ = false;
};

}  // namespace mobot::api
