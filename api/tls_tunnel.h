#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/ssl/context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/ssl/ssl_stream.hpp>

namespace mobot::api {

// What the TLS front has done, for /metrics. Thread-safe.
struct TlsCounters {
  std::atomic<std::uint64_t> handshakes{0};          // connections that became https/wss
  std::atomic<std::uint64_t> handshake_failures{0};  // plain http, garbage, timeouts, bad versions
};

struct TlsTunnelTimeouts {
  // A client has this long to complete its handshake; a silent or slow one is closed.
  std::chrono::milliseconds handshake{std::chrono::seconds(10)};
  // The client has this long to take one chunk of the server's bytes; one that reads nothing for
  // so long is gone, and the connection is closed (a slow reader that still reads is kept).
  std::chrono::milliseconds write_stall{std::chrono::seconds(60)};
  // The exchange of close_notify alerts at the end.
  std::chrono::milliseconds shutdown{std::chrono::seconds(2)};
};

// One TLS connection, decrypted in front of the plain HTTP/WebSocket sessions. After the handshake
// it makes a connected AF_UNIX socket pair, hands one end to `open` as if it were the client's TCP
// connection (the sessions then run exactly as they do for plain http, StreamSession's
// non-blocking writes included), and pumps the bytes both ways between the TLS stream and its own
// end: at most one chunk in flight each way, so a side that does not read holds the other back
// instead of growing a buffer. When either side ends, both are closed; a server side that closes
// first gets the client a close_notify. A client that is not speaking TLS (plain http, garbage) or
// does not finish its handshake in time is closed without a byte sent.
class TlsTunnel : public std::enable_shared_from_this<TlsTunnel> {
 public:
  // Runs once, on the tunnel's strand, with the plain end (an asio tcp::socket over the AF_UNIX
  // socket: remote_endpoint() means nothing on it) and the client's real address "ip:port".
  using Open = std::function<void(boost::asio::ip::tcp::socket plain_end, std::string peer)>;

  // `socket`: the accepted connection, on a strand of its own. `session_executor`: where the
  // plain end's operations run (the session's strand).
  TlsTunnel(boost::asio::ip::tcp::socket socket, boost::asio::ssl::context& context,
            TlsCounters& counters, TlsTunnelTimeouts timeouts,
            boost::asio::any_io_executor session_executor, Open open);
  void start();

 private:
  static constexpr std::size_t kChunkBytes = 16 * 1024;  // one TLS record

  boost::asio::ip::tcp::socket& tcp() { return tls_.next_layer(); }
  void await_client_hello();
  void on_first_bytes(boost::system::error_code error);
  void on_handshake(boost::system::error_code error);
  void fail_handshake(const std::string& reason);
  // The socket pair, its far end handed to open_; false (and everything closed) when the system
  // has no socket to give.
  bool open_pair();
  void read_client();
  void on_client_bytes(boost::system::error_code error, std::size_t bytes);
  void on_passed_to_server(boost::system::error_code error);
  void read_server();
  void on_server_bytes(boost::system::error_code error, std::size_t bytes);
  void on_sent_to_client(boost::system::error_code error);
  void server_side_ended();
  void start_tls_shutdown();
  void arm_deadline(std::chrono::milliseconds timeout);
  void disarm_deadline();
  void on_deadline(boost::system::error_code error);
  void close_all();

  boost::beast::ssl_stream<boost::asio::ip::tcp::socket> tls_;
  boost::asio::local::stream_protocol::socket local_;
  // One deadline at a time: the handshake's, then a write's to the client, then the shutdown's.
  boost::asio::steady_timer deadline_;
  TlsCounters& counters_;
  TlsTunnelTimeouts timeouts_;
  boost::asio::any_io_executor session_executor_;
  Open open_;
  std::string peer_;
  std::array<char, kChunkBytes> from_client_{};
  std::array<char, kChunkBytes> from_server_{};
  // All on the tunnel's strand.
  bool handshake_done_ = false;
  bool reading_client_ = false;  // a TLS read is in flight (the shutdown must not overlap it)
  bool shutting_down_ = false;   // the server side ended: close_notify, then close
  bool closed_ = false;
};

}  // namespace mobot::api
