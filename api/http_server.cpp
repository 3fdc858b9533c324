#include "api/http_server.h"

#include <spdlog/spdlog.h>
#include <algorithm>
#include <cerrno>
#include <boost/asio/strand.hpp>
#include <thread>

#include "api/http_session.h"
#include "api/prometheus_text.h"

namespace mobot::api {

HttpServer::HttpServer(boost::asio::io_context& io, RestApi& rest, StreamHub& hub,
                       const Ports& ports, boost::asio::ssl::context* tls,
                       TlsTunnelTimeouts tls_timeouts)
    : io_(io),
      rest_(rest),
      hub_(hub),
      ports_(ports),
      tls_(tls),
      tls_timeouts_(tls_timeouts),
      acceptor_(boost::asio::make_strand(io)),
      accept_pause_(acceptor_.get_executor()),
      token_watch_(io.get_executor(), hub, ports.tokens) {
  // The stream sessions are written from this server's io threads; a batch is shared by as many
  // of them as there are cores to run them.
  hub_.set_executor(io_.get_executor(), std::max(1U, std::thread::hardware_concurrency()));
}

boost::asio::ip::tcp::endpoint HttpServer::listen(const HttpOptions& options) {
  const boost::asio::ip::tcp::endpoint endpoint{boost::asio::ip::make_address(options.bind_address),
                                                options.port};
  acceptor_.open(endpoint.protocol());
  acceptor_.set_option(boost::asio::socket_base::reuse_address(true));
  acceptor_.bind(endpoint);
  acceptor_.listen(boost::asio::socket_base::max_listen_connections);
  token_watch_.start();
  accept_next();
  return acceptor_.local_endpoint();
}

void HttpServer::stop() {
  token_watch_.stop();
  boost::asio::post(acceptor_.get_executor(), [this] {
    boost::system::error_code ignored;
    acceptor_.close(ignored);
  });
}

void HttpServer::accept_next() {
  acceptor_.async_accept(
      boost::asio::make_strand(io_),
      [this](boost::system::error_code error, boost::asio::ip::tcp::socket socket) {
        if (error == boost::asio::error::operation_aborted) return;
        if (error) {
          on_accept_error(error);
          return;
        }
        if (hub_.clients().size() >= kMaxConnections) {
          // Full: the newcomer is closed at once rather than taking the descriptors and memory
          // the connections already served need.
          connections_refused_.fetch_add(1, std::memory_order_relaxed);
          boost::system::error_code ignored;
          socket.close(ignored);
        } else if (tls_ != nullptr) {
          serve_tls(std::move(socket));
        } else {
          std::make_shared<HttpSession>(std::move(socket), rest_, hub_, ports_)->start();
        }
        if (acceptor_.is_open()) accept_next();
      });
}

void HttpServer::on_accept_error(boost::system::error_code error) {
  accept_errors_.fetch_add(1, std::memory_order_relaxed);
  // Out of descriptors (or memory), accept fails at once every time it is tried: a pause lets
  // connections close meanwhile instead of spinning a core on the error.
  const bool exhausted = error == boost::asio::error::no_descriptors ||
                         error.value() == ENFILE || error == boost::asio::error::no_buffer_space ||
                         error == boost::asio::error::no_memory;
  if (!exhausted) {
    spdlog::warn("accept failed: {}", error.message());
    if (acceptor_.is_open()) accept_next();
    return;
  }
  spdlog::warn("accept failed: {}; accepting again in {} ms", error.message(),
               kAcceptPause.count());
  accept_pause_.expires_after(kAcceptPause);
  accept_pause_.async_wait([this](boost::system::error_code wait_error) {
    if (!wait_error && acceptor_.is_open()) accept_next();
  });
}

void HttpServer::serve_tls(boost::asio::ip::tcp::socket socket) {
  auto open = [this](boost::asio::ip::tcp::socket plain_end, std::string peer) {
    std::make_shared<HttpSession>(std::move(plain_end), rest_, hub_, ports_,
                                  ConnectionOrigin{std::move(peer), true})
        ->start();
  };
  std::make_shared<TlsTunnel>(std::move(socket), *tls_, tls_counters_, tls_timeouts_,
                              boost::asio::make_strand(io_), std::move(open))
      ->start();
}

std::string HttpServer::metrics_text() const {
  std::string out;
  append_metric(out, "mobot_http_connections_refused_total", "counter",
                "Connections closed as they came because the server had its maximum open.",
                static_cast<double>(connections_refused_.load()));
  append_metric(out, "mobot_http_accept_errors_total", "counter",
                "Failed accepts (out of file descriptors, memory, ...).",
                static_cast<double>(accept_errors_.load()));
  if (tls_ == nullptr) return out;
  append_metric(out, "mobot_tls_handshakes_total", "counter",
                "TLS connections whose handshake completed.",
                static_cast<double>(tls_counters_.handshakes.load()));
  append_metric(out, "mobot_tls_handshake_failures_total", "counter",
                "Connections closed before a TLS handshake completed: plain http, bytes that "
                "are not TLS, failed or timed-out handshakes.",
                static_cast<double>(tls_counters_.handshake_failures.load()));
  return out;
}

}  // namespace mobot::api
