#include "api/tls_tunnel.h"

#include <spdlog/spdlog.h>
#include <sys/socket.h>
#include <unistd.h>

#include <boost/asio/dispatch.hpp>
#include <boost/asio/ssl/error.hpp>
#include <boost/asio/write.hpp>
#include <cerrno>
#include <cstring>

namespace mobot::api {
namespace {

// Every TLS connection starts with a handshake record (RFC 8446 5.1, ContentType handshake); a
// plain-http request starts with a method's letters.
constexpr unsigned char kTlsHandshakeRecord = 0x16;

}  // namespace

TlsTunnel::TlsTunnel(boost::asio::ip::tcp::socket socket, boost::asio::ssl::context& context,
                     TlsCounters& counters, TlsTunnelTimeouts timeouts,
                     boost::asio::any_io_executor session_executor, Open open)
    : tls_(std::move(socket), context),
      local_(tls_.get_executor()),
      deadline_(tls_.get_executor()),
      counters_(counters),
      timeouts_(timeouts),
      session_executor_(std::move(session_executor)),
      open_(std::move(open)) {}

void TlsTunnel::start() {
  boost::system::error_code error;
  const auto peer = tcp().remote_endpoint(error);
  if (!error) peer_ = peer.address().to_string() + ":" + std::to_string(peer.port());
  boost::asio::dispatch(tls_.get_executor(), [self = shared_from_this()] {
    self->arm_deadline(self->timeouts_.handshake);
    self->await_client_hello();
  });
}

void TlsTunnel::await_client_hello() {
  tcp().async_wait(boost::asio::ip::tcp::socket::wait_read,
                   [self = shared_from_this()](boost::system::error_code error) {
                     self->on_first_bytes(error);
                   });
}

void TlsTunnel::on_first_bytes(boost::system::error_code error) {
  if (closed_) return;
  if (error) {
    fail_handshake(error.message());
    return;
  }
  // A look at the first byte before OpenSSL reads anything: what is not TLS is closed without a
  // byte sent (OpenSSL would answer some of it with an alert record).
  unsigned char first = 0;
  const ssize_t peeked = ::recv(tcp().native_handle(), &first, 1, MSG_PEEK | MSG_DONTWAIT);
  if (peeked < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) {
    await_client_hello();
    return;
  }
  if (peeked <= 0) {
    fail_handshake("closed before a ClientHello");
    return;
  }
  if (first != kTlsHandshakeRecord) {
    fail_handshake("not a TLS handshake (plain http?)");
    return;
  }
  tls_.async_handshake(boost::asio::ssl::stream_base::server,
                       [self = shared_from_this()](boost::system::error_code handshake_error) {
                         self->on_handshake(handshake_error);
                       });
}

void TlsTunnel::on_handshake(boost::system::error_code error) {
  if (closed_) return;
  if (error) {
    fail_handshake(error.message());
    return;
  }
  handshake_done_ = true;
  disarm_deadline();
  counters_.handshakes.fetch_add(1, std::memory_order_relaxed);
  if (!open_pair()) return;
  read_client();
  read_server();
}

void TlsTunnel::fail_handshake(const std::string& reason) {
  counters_.handshake_failures.fetch_add(1, std::memory_order_relaxed);
  spdlog::debug("TLS handshake with {} failed: {}", peer_, reason);
  close_all();
}

bool TlsTunnel::open_pair() {
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) {
    spdlog::warn("TLS connection from {} closed: no socket pair ({})", peer_,
                 std::strerror(errno));
    close_all();
    return false;
  }
  boost::system::error_code error;
  local_.assign(boost::asio::local::stream_protocol(), fds[0], error);
  if (error) {
    ::close(fds[0]);
    ::close(fds[1]);
    close_all();
    return false;
  }
  // The sessions take a tcp::socket; every stream operation they use works on any stream socket.
  boost::asio::ip::tcp::socket plain_end(session_executor_);
  plain_end.assign(boost::asio::ip::tcp::v4(), fds[1], error);
  if (error) {
    ::close(fds[1]);
    close_all();
    return false;
  }
  open_(std::move(plain_end), peer_);
  return true;
}

void TlsTunnel::read_client() {
  reading_client_ = true;
  tls_.async_read_some(boost::asio::buffer(from_client_),
                       [self = shared_from_this()](boost::system::error_code error,
                                                   std::size_t bytes) {
                         self->on_client_bytes(error, bytes);
                       });
}

void TlsTunnel::on_client_bytes(boost::system::error_code error, std::size_t bytes) {
  reading_client_ = false;
  if (closed_) return;
  if (shutting_down_) {
    // The read was cancelled (or finished) because the server side ended: now the TLS stream is
    // free for the close_notify exchange.
    start_tls_shutdown();
    return;
  }
  if (error == boost::asio::error::eof) {
    // close_notify: the client sends nothing more. The session reads the end of its requests, and
    // its answer, still on its way, closes the tunnel when it is out.
    boost::system::error_code ignored;
    local_.shutdown(boost::asio::socket_base::shutdown_send, ignored);
    return;
  }
  if (error) {
    // Reset, or a connection cut without close_notify (ssl::error::stream_truncated).
    close_all();
    return;
  }
  boost::asio::async_write(local_, boost::asio::buffer(from_client_.data(), bytes),
                           [self = shared_from_this()](boost::system::error_code write_error,
                                                       std::size_t) {
                             self->on_passed_to_server(write_error);
                           });
}

void TlsTunnel::on_passed_to_server(boost::system::error_code error) {
  if (closed_ || shutting_down_) return;
  // A session that closed its end stops taking bytes; what it said last may still be on its way
  // to the client, and its end of file (read_server) ends the tunnel.
  if (error) return;
  read_client();
}

void TlsTunnel::read_server() {
  local_.async_read_some(boost::asio::buffer(from_server_),
                         [self = shared_from_this()](boost::system::error_code error,
                                                     std::size_t bytes) {
                           self->on_server_bytes(error, bytes);
                         });
}

void TlsTunnel::on_server_bytes(boost::system::error_code error, std::size_t bytes) {
  if (closed_) return;
  if (error) {
    server_side_ended();
    return;
  }
  arm_deadline(timeouts_.write_stall);
  boost::asio::async_write(tls_, boost::asio::buffer(from_server_.data(), bytes),
                           [self = shared_from_this()](boost::system::error_code write_error,
                                                       std::size_t) {
                             self->on_sent_to_client(write_error);
                           });
}

void TlsTunnel::on_sent_to_client(boost::system::error_code error) {
  if (closed_) return;
  disarm_deadline();
  if (error) {
    close_all();
    return;
  }
  read_server();
}

void TlsTunnel::server_side_ended() {
  shutting_down_ = true;
  // A TLS read and the shutdown's own read must not overlap: the pending read is cancelled, and
  // its handler starts the shutdown.
  if (reading_client_) {
    boost::system::error_code ignored;
    tcp().cancel(ignored);
    return;
  }
  start_tls_shutdown();
}

void TlsTunnel::start_tls_shutdown() {
  if (closed_) return;
  arm_deadline(timeouts_.shutdown);
  tls_.async_shutdown([self = shared_from_this()](boost::system::error_code) { self->close_all(); });
}

void TlsTunnel::arm_deadline(std::chrono::milliseconds timeout) {
  deadline_.expires_after(timeout);
  deadline_.async_wait(
      [self = shared_from_this()](boost::system::error_code error) { self->on_deadline(error); });
}

void TlsTunnel::disarm_deadline() {
  // Cancels the wait; a handler already queued sees the far expiry and does nothing.
  deadline_.expires_at(boost::asio::steady_timer::time_point::max());
}

void TlsTunnel::on_deadline(boost::system::error_code error) {
  if (error == boost::asio::error::operation_aborted || closed_) return;
  if (deadline_.expiry() > boost::asio::steady_timer::clock_type::now()) return;
  if (!handshake_done_) {
    fail_handshake("no handshake within the time allowed");
    return;
  }
  if (!shutting_down_) spdlog::debug("TLS client {} took nothing for too long: closed", peer_);
  close_all();
}

void TlsTunnel::close_all() {
  if (closed_) return;
  closed_ = true;
  disarm_deadline();
  boost::system::error_code ignored;
  local_.close(ignored);
  tcp().close(ignored);
}

}  // namespace mobot::api
