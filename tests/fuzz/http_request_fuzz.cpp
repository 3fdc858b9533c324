// libFuzzer target: HTTP requests as the server reads them (api/http_session.cpp): Beast's request
// parser with the server's limits, the header first (16 KiB, the largest body limit of any
// endpoint), then the body with its endpoint's limit, in reads of varying size; then what our own
// code reads of a parsed request: the path and the query string (?token= of a stream upgrade,
// percent-decoded), the Upgrade check with its key and version, the bearer token and the route
// (RestApi::handle against the fake robot of the unit tests). Beyond not crashing: no header over
// the limit and no body over its endpoint's limit is ever accepted, and each request is answered
// once, never with a 5xx.
#include <algorithm>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket/rfc6455.hpp>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "api/http_types.h"
#include "api/rest_api.h"
#include "api/stream_hub.h"
#include "api/websocket_frames.h"
#include "fake_ports.h"

namespace {

using namespace mobot::api;
using RequestParser = http::request_parser<http::string_body>;

void check(bool condition) {
  if (!condition) __builtin_trap();
}

// Bytes as a socket delivers them: `read_bytes` at a time, appended to what was received.
class Connection {
 public:
  Connection(std::string_view bytes, std::size_t read_bytes)
      : bytes_(bytes), read_bytes_(read_bytes) {}

  // Feeds the parser until `done` or an error; false when the input ran out first.
  template <class Done>
  bool read(RequestParser& parser, boost::beast::error_code& error, Done done) {
    bool wants_more = consumed_ == received_.size();
    while (!done()) {
      if (wants_more) {
        if (delivered_ == bytes_.size()) return false;
        const std::size_t take = std::min(read_bytes_, bytes_.size() - delivered_);
        received_.append(bytes_.substr(delivered_, take));
        delivered_ += take;
      }
      error = {};
      const std::size_t used = parser.put(
          boost::asio::buffer(received_.data() + consumed_, received_.size() - consumed_), error);
      consumed_ += used;
      if (error && error != http::error::need_more) return true;
      wants_more = error == http::error::need_more || used == 0 || consumed_ == received_.size();
    }
    return true;
  }

  std::size_t consumed() const { return consumed_; }

 private:
  std::string_view bytes_;
  std::size_t read_bytes_;
  std::string received_;
  std::size_t delivered_ = 0;
  std::size_t consumed_ = 0;
};

// What of a parsed request our code reads before it is routed.
void read_request(const Request& request) {
  const std::string_view target = request.target();
  const std::string_view path = target_path(target);
  check(target.substr(0, path.size()) == path);
  const std::string token = query_parameter(target, "token");
  check(token.size() <= target.size());
  check(percent_decode(path).size() <= path.size());
  if (boost::beast::websocket::is_upgrade(request)) {
    const auto key = request[http::field::sec_websocket_key];
    if (!key.empty() && request[http::field::sec_websocket_version] == "13") {
      check(websocket_accept_key(key).size() == 28);
    }
  }
}

void route(const Request& request) {
  test::FakePorts robot;
  StreamHub hub(StreamOptions{});
  RestApi rest(robot.ports(true), hub, {"/nonexistent/mobot-web", "fuzz"});
  rest.stream_caller(request);
  if (boost::beast::websocket::is_upgrade(request)) return;  // the stream session takes over
  int replies = 0;
  rest.handle(
      request,
      [&](Response response) {
        ++replies;
        check(response.result_int() < 500);
      },
      ClientContext{1, "127.0.0.1:4000"});
  check(replies == 1);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  // The first byte picks the read size, as a socket returns whatever has arrived.
  Connection connection(std::string_view(reinterpret_cast<const char*>(data) + 1, size - 1),
                        1 + data[0] % 128);
  RequestParser parser;
  parser.header_limit(kMaxRequestHeaderBytes);
  // As the session: Content-Length is checked against the largest limit while the header is
  // parsed, and against the endpoint's once the path is known.
  parser.body_limit(RestApi::kMaxBodyLimit);
  boost::beast::error_code error;
  if (!connection.read(parser, error, [&] { return parser.is_header_done(); }) || error) return 0;
  check(connection.consumed() <= kMaxRequestHeaderBytes);
  const auto& header = parser.get();
  const std::size_t body_limit = RestApi::body_limit(header.method(), header.target());
  check(body_limit <= RestApi::kMaxBodyLimit);
  if (const auto length = parser.content_length(); length && *length > body_limit) return 0;
  parser.body_limit(body_limit);
  if (!connection.read(parser, error, [&] { return parser.is_done(); }) || error) return 0;
  const Request request = parser.release();
  check(request.body().size() <= body_limit);
  read_request(request);
  route(request);
  return 0;
}
