#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/ssl/context.hpp>

#include "api/ports/ports.h"
#include "api/rest_api.h"
#include "api/stream_hub.h"
#include "api/tls_tunnel.h"
#include "api/token_watch.h"

namespace mobot::api {

struct HttpOptions {
  std::string bind_address = "127.0.0.1";
  std::uint16_t port = 8080;
};

// Accepts TCP connections and gives each its own HttpSession (Beast's advanced_server shape). With
// a TLS context, every connection goes through a TlsTunnel first: the port then speaks https and
// wss only.
class HttpServer {
 public:
  // `tls`: null for plain http; otherwise it must outlive the server.
  HttpServer(boost::asio::io_context& io, RestApi& rest, StreamHub& hub, const Ports& ports,
             boost::asio::ssl::context* tls = nullptr,
             TlsTunnelTimeouts tls_timeouts = TlsTunnelTimeouts{});

  // Binds and starts accepting; returns the bound endpoint (port 0 picks a free one).
  boost::asio::ip::tcp::endpoint listen(const HttpOptions& options);
  void stop();
  bool secure() const { return tls_ != nullptr; }
  // The TLS front's counters in the Prometheus text format (nothing for plain http).
  std::string metrics_text() const;

 private:
  void accept_next();
  void on_accept_error(boost::system::error_code error);

  // Open connections (HTTP and stream) the server keeps at most; mobotd raises its descriptor
  // limit above this at start. 1000 half-open connections (slow-loris) fit with room to spare.
  static constexpr std::size_t kMaxConnections = 8000;
  static constexpr std::chrono::milliseconds kAcceptPause{100};
  void serve_tls(boost::asio::ip::tcp::socket socket);

  boost::asio::io_context& io_;
  RestApi& rest_;
  StreamHub& hub_;
  Ports ports_;
  boost::asio::ssl::context* tls_;
  TlsTunnelTimeouts tls_timeouts_;
  TlsCounters tls_counters_;
  boost::asio::ip::tcp::acceptor acceptor_;
  boost::asio::steady_timer accept_pause_;  // on the acceptor's strand
  std::atomic<std::uint64_t> connections_refused_{0};
  std::atomic<std::uint64_t> accept_errors_{0};
  TokenWatch token_watch_;  // closes the streams of revoked and expired tokens
};

}  // namespace mobot::api
