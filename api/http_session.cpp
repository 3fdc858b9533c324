#include "api/http_session.h"

#include <spdlog/spdlog.h>

#include <boost/asio/dispatch.hpp>
#include <boost/beast/websocket/rfc6455.hpp>
#include <chrono>

#include "api/stream_session.h"
#include "api/wall_clock.h"
#include "api/websocket_frames.h"

namespace mobot::api {
namespace {

constexpr auto kIdleTimeout = std::chrono::seconds(60);
// A request's header (or, between requests, the next one) must come within this: a client that
// opens connections and trickles nothing, or a byte now and then (slow-loris), holds each only so
// long. A body may take kIdleTimeout (a map import over a thin link).
constexpr auto kHeaderTimeout = std::chrono::seconds(15);
// Requests a connection may make: this many a second on average, this many at once. The dashboard
// makes a few a second; a script polling in a tight loop on one connection is held to this.
constexpr double kRequestsPerSecond = 200.0;
constexpr double kRequestBurst = 400.0;
constexpr std::size_t kHeaderLimit = kMaxRequestHeaderBytes;

// RFC 6797: browsers that saw it use https for this host for a year, never plain http.
constexpr std::string_view kHsts = "max-age=31536000";

ConnectionOrigin tcp_origin(const boost::asio::ip::tcp::socket& socket) {
  boost::system::error_code error;
  const auto peer = socket.remote_endpoint(error);
  if (error) return {};
  return {peer.address().to_string() + ":" + std::to_string(peer.port()), false};
}

}  // namespace

HttpSession::HttpSession(boost::asio::ip::tcp::socket socket, RestApi& rest, StreamHub& hub,
                         const Ports& ports)
    : HttpSession(std::move(socket), rest, hub, ports, ConnectionOrigin{}) {}

HttpSession::HttpSession(boost::asio::ip::tcp::socket socket, RestApi& rest, StreamHub& hub,
                         const Ports& ports, ConnectionOrigin origin)
    : stream_(std::move(socket)),
      rest_(rest),
      hub_(hub),
      ports_(ports),
      secure_(origin.secure),
      request_budget_(kRequestsPerSecond, kRequestBurst) {
  if (origin.peer_address.empty() && !origin.secure) origin = tcp_origin(stream_.socket());
  client_.address = std::move(origin.peer_address);
  registration_ = hub_.clients().open(client_.address, unix_now_s());
  client_.id = registration_->id();
}

void HttpSession::start() {
  boost::asio::dispatch(stream_.get_executor(),
                        [self = shared_from_this()] { self->read_header(); });
}

void HttpSession::read_header() {
  parser_.emplace();
  parser_->header_limit(kHeaderLimit);
  // Beast checks Content-Length against the body limit while it parses the header, before the
  // path is known: start with the largest limit any endpoint allows and narrow it in on_header.
  parser_->body_limit(RestApi::kMaxBodyLimit);
  stream_.expires_after(kHeaderTimeout);
  http::async_read_header(stream_, buffer_, *parser_,
                          [self = shared_from_this()](boost::beast::error_code error, std::size_t) {
                            self->on_header(error);
                          });
}

void HttpSession::on_header(boost::beast::error_code error) {
  if (error == http::error::header_limit) {
    Request bare;
    send(error_response(bare, 431, "header_too_large", "request header too large"), true);
    return;
  }
  if (error == http::error::body_limit) {
    Request bare;
    send(error_response(bare, 413, "body_too_large", "request body too large"), true);
    return;
  }
  if (error) {
    answer_read_error(error);
    return;
  }
  const auto& header = parser_->get();
  parser_->body_limit(RestApi::body_limit(header.method(), header.target()));
  if (const auto length = parser_->content_length();
      length && *length > RestApi::body_limit(header.method(), header.target())) {
    Request bare;
    bare.version(header.version());
    send(error_response(bare, 413, "body_too_large", "request body too large"), true);
    return;
  }
  stream_.expires_after(kIdleTimeout);
  http::async_read(stream_, buffer_, *parser_,
                   [self = shared_from_this()](boost::beast::error_code read_error, std::size_t) {
                     self->on_body(read_error);
                   });
}

// A client that went away or took too long is not answered; bytes that are not HTTP are
// (RFC 9112 section 3: a request line or header that does not parse gets a 400).
void HttpSession::answer_read_error(boost::beast::error_code error) {
  if (error == http::error::end_of_stream || error == boost::beast::error::timeout ||
      error == boost::asio::error::connection_reset || error == boost::asio::error::eof ||
      error == boost::asio::error::operation_aborted) {
    close();
    return;
  }
  Request bare;
  send(error_response(bare, 400, "bad_request", error.message()), true);
}

void HttpSession::on_body(boost::beast::error_code error) {
  if (error == http::error::body_limit) {
    Request bare;
    send(error_response(bare, 413, "body_too_large", "request body too large"), true);
    return;
  }
  if (error) {
    answer_read_error(error);
    return;
  }
  Request request = parser_->release();
  if (spdlog::should_log(spdlog::level::debug)) {
    spdlog::debug("{} {} {}", client_.address, std::string_view(request.method_string()),
                  redacted_target(request.target()));
  }
  if (refused_for_rate(request)) return;
  if (boost::beast::websocket::is_upgrade(request)) {
    upgrade_to_stream(request);
    return;
  }
  answer(request);
}

bool HttpSession::refused_for_rate(const Request& request) {
  const auto now = TokenBucket::Clock::now();
  if (request_budget_.take(now)) return false;
  const auto wait = std::chrono::ceil<std::chrono::seconds>(request_budget_.wait(now));
  Response response =
      error_response(request, 429, "rate_limited",
                     "more than " + std::to_string(static_cast<int>(kRequestsPerSecond)) +
                         " requests a second on this connection");
  response.set(http::field::retry_after, std::to_string(std::max<long long>(1, wait.count())));
  rest_.count_response(429);
  send(std::move(response), !request.keep_alive());
  return true;
}

void HttpSession::answer(const Request& request) {
  // The robot may take its time (a plan, a commit): that is not the client being idle, and nothing
  // is read from it meanwhile. The timer starts again with the write.
  stream_.expires_never();
  rest_.handle(
      request,
      [self = shared_from_this()](Response response) {
        // Any thread; the session lives until the response is written from its strand.
        boost::asio::dispatch(self->stream_.get_executor(),
                              [self, response = std::move(response)]() mutable {
                                const bool close_after = !response.keep_alive();
                                self->send(std::move(response), close_after);
                              });
      },
      client_);
}

void HttpSession::send(Response response, bool close_after) {
  auto shared = std::make_shared<Response>(std::move(response));
  if (close_after) shared->keep_alive(false);
  if (secure_) shared->set(http::field::strict_transport_security, kHsts);
  stream_.expires_after(kIdleTimeout);
  http::async_write(stream_, *shared,
                    [self = shared_from_this(), shared, close_after](boost::beast::error_code error,
                                                                     std::size_t bytes) {
                      self->registration_->add_sent(bytes);
                      if (error || close_after) {
                        self->close();
                        return;
                      }
                      self->read_header();
                    });
}

void HttpSession::upgrade_to_stream(const Request& request) {
  if (target_path(request.target()) != "/api/v1/stream") {
    send(error_response(request, 404, "not_found", "WebSocket is served at /api/v1/stream"), true);
    return;
  }
  const auto caller = rest_.stream_caller(request);
  if (!caller) {
    rest_.count_response(401);
    send(error_response(request, 401, "unauthorized", "missing or unknown ?token="), true);
    return;
  }
  const auto key = request[http::field::sec_websocket_key];
  if (key.empty() || request[http::field::sec_websocket_version] != "13") {
    send(error_response(request, 400, "bad_upgrade", "WebSocket version 13 with a key is required"),
         true);
    return;
  }
  rest_.count_response(101);
  auto handshake = std::make_shared<std::string>(
      "HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
      "Sec-WebSocket-Accept: " +
      websocket_accept_key(key) + "\r\nServer: mobotd\r\n" +
      (secure_ ? "Strict-Transport-Security: " + std::string(kHsts) + "\r\n" : std::string{}) +
      "\r\n");
  stream_.expires_never();
  boost::asio::async_write(
      stream_, boost::asio::buffer(*handshake),
      [self = shared_from_this(), handshake, caller = *caller](boost::beast::error_code error,
                                                               std::size_t) {
        if (error) {
          self->close();
          return;
        }
        const auto pending = self->buffer_.data();
        std::string already_received(static_cast<const char*>(pending.data()), pending.size());
        // The same connection, now a stream: it keeps its registration.
        self->registration_->became_stream();
        self->registration_->identify(caller);
        auto session = std::make_shared<StreamSession>(
            self->stream_.release_socket(), self->hub_, self->ports_,
            StreamPeer{caller, self->client_, std::move(self->registration_)},
            std::move(already_received));
        session->start();
      });
}

void HttpSession::close() {
  boost::beast::error_code ignored;
  stream_.socket().shutdown(boost::asio::ip::tcp::socket::shutdown_send, ignored);
  stream_.close();
}

}  // namespace mobot::api
