#include "api/http_server.h"

#include <spdlog/spdlog.h>
#include <algorithm>
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
      acceptor_(boost::asio::make_strand(io)) {
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
  accept_next();
  return acceptor_.local_endpoint();
}

void HttpServer::stop() {
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
          spdlog::warn("accept failed: {}", error.message());
        } else if (tls_ != nullptr) {
          serve_tls(std::move(socket));
        } else {
          std::make_shared<HttpSession>(std::move(socket), rest_, hub_, ports_)->start();
        }
        if (acceptor_.is_open()) accept_next();
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
  if (tls_ == nullptr) return {};
  std::string out;
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
