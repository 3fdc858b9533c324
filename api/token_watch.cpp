#include "api/token_watch.h"

#include <boost/asio/strand.hpp>

namespace mobot::api {

TokenWatch::TokenWatch(boost::asio::any_io_executor executor, StreamHub& hub,
                       TokenAdminPort& tokens, std::chrono::milliseconds period)
    : hub_(hub), tokens_(tokens), period_(period), timer_(boost::asio::make_strand(executor)) {}

TokenWatch::~TokenWatch() { stop(); }

void TokenWatch::start() {
  *running_ = true;
  schedule();
}

void TokenWatch::stop() {
  // The timer is not cancelled from here (its handler may be re-arming it on an io thread): its
  // next expiry sees the flag and ends the watch without touching it.
  *running_ = false;
}

void TokenWatch::check_now() {
  hub_.close_inactive_tokens([this](std::int64_t token_id) { return tokens_.is_active(token_id); });
}

void TokenWatch::schedule() {
  timer_.expires_after(period_);
  timer_.async_wait([this, running = running_](boost::system::error_code error) {
    if (error || !*running) return;
    check_now();
    schedule();
  });
}

}  // namespace mobot::api
