#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>

#include "api/ports/ports.h"
#include "api/rest_api.h"
#include "api/stream_hub.h"

namespace mobot::api {

struct HttpOptions {
  std::string bind_address = "127.0.0.1";
  std::uint16_t port = 8080;
};

// Accepts TCP connections and gives each its own HttpSession (Beast's advanced_server shape).
class HttpServer {
 public:
  HttpServer(boost::asio::io_context& io, RestApi& rest, StreamHub& hub, const Ports& ports);

  // Binds and starts accepting; returns the bound endpoint (port 0 picks a free one).
  boost::asio::ip::tcp::endpoint listen(const HttpOptions& options);
  void stop();

 private:
  void accept_next();

  boost::asio::io_context& io_;
  RestApi& rest_;
  StreamHub& hub_;
  Ports ports_;
  boost::asio::ip::tcp::acceptor acceptor_;
};

}  // namespace mobot::api
