#pragma once

#include <memory>
#include <optional>
#include <string>

#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

#include "api/http_types.h"
#include "api/ports/ports.h"
#include "api/rest_api.h"
#include "api/stream_hub.h"
#include "api/token_bucket.h"

namespace mobot::api {

// How a connection came: straight over TCP, or through a TlsTunnel, whose plain end the session
// then reads and writes (and whose client's address it takes, the socket's being the tunnel's).
struct ConnectionOrigin {
  std::string peer_address;  // "ip:port" of the client
  bool secure = false;       // https/wss: responses carry Strict-Transport-Security
};

// One HTTP/1.1 connection with keep-alive. Reads the header first so the body limit can depend on
// the endpoint (8 MiB for map import, 64 KiB otherwise), answers REST requests, and hands the
// socket to a StreamSession on a WebSocket upgrade of /api/v1/stream. A response may come from
// another thread (a port's Completion); it is written on the session's strand, and the next
// request is read only once it is out.
class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  // A plain TCP connection: the client is the socket's peer.
  HttpSession(boost::asio::ip::tcp::socket socket, RestApi& rest, StreamHub& hub,
              const Ports& ports);
  HttpSession(boost::asio::ip::tcp::socket socket, RestApi& rest, StreamHub& hub,
              const Ports& ports, ConnectionOrigin origin);
  void start();

 private:
  void read_header();
  void on_header(boost::beast::error_code error);
  void on_body(boost::beast::error_code error);
  void answer_read_error(boost::beast::error_code error);
  void answer(const Request& request);
  // 429 for a request over the connection's rate; false when it may be answered.
  bool refused_for_rate(const Request& request);
  void send(Response response, bool close_after);
  void upgrade_to_stream(const Request& request);
  void close();

  boost::beast::tcp_stream stream_;
  boost::beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  RestApi& rest_;
  StreamHub& hub_;
  Ports ports_;
  ClientRegistry::Registration registration_;
  ClientContext client_;
  bool secure_ = false;
  TokenBucket request_budget_;
};

}  // namespace mobot::api
