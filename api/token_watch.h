#pragma once

#include <atomic>
#include <chrono>
#include <memory>

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/steady_timer.hpp>

#include "api/ports/token_admin_port.h"
#include "api/stream_hub.h"

namespace mobot::api {

// Closes the open streams of a token that stopped authenticating: revoked (by REST, or by
// `mobotd token revoke` in another process) or past its expiry. A request is refused at once
// anyway; a stream authenticated when it opened, so it is checked every `period`.
class TokenWatch {
 public:
  TokenWatch(boost::asio::any_io_executor executor, StreamHub& hub, TokenAdminPort& tokens,
             std::chrono::milliseconds period = std::chrono::milliseconds(500));
  ~TokenWatch();
  TokenWatch(const TokenWatch&) = delete;
  TokenWatch& operator=(const TokenWatch&) = delete;

  void start();
  void stop();
  // Checks now, between the periodic checks (after a revocation through REST).
  void check_now();

 private:
  void schedule();

  StreamHub& hub_;
  TokenAdminPort& tokens_;
  const std::chrono::milliseconds period_;
  boost::asio::steady_timer timer_;
  // Whether the watch runs: the timer's handler may still be queued when stop() returns, and then
  // touches nothing of the watch. The watch must outlive the io threads' last handler (the server
  // joins them before destroying it).
  std::shared_ptr<std::atomic<bool>> running_ = std::make_shared<std::atomic<bool>>(false);
};

}  // namespace mobot::api
