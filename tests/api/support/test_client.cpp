#include "support/test_client.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <openssl/err.h>
#include <openssl/ssl.h>
#include <openssl/x509v3.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <cerrno>
#include <csignal>
#include <random>

#include "support/deadline.h"

namespace mobot::testing {

namespace beast = boost::beast;
namespace http = beast::http;
using tcp = boost::asio::ip::tcp;

namespace {

std::string lower(std::string text) {
  for (auto& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

// Parses "HTTP/1.1 200 OK\r\nName: value\r\n...\r\n\r\n" (without the body).
HttpReply parse_response_head(std::string_view head) {
  HttpReply reply;
  const auto line_end = head.find("\r\n");
  const std::string_view status_line = head.substr(0, line_end);
  const auto space = status_line.find(' ');
  if (space != std::string_view::npos) {
    reply.status = std::atoi(std::string(status_line.substr(space + 1, 3)).c_str());
  }
  std::size_t at = line_end == std::string_view::npos ? head.size() : line_end + 2;
  while (at < head.size()) {
    const auto end = head.find("\r\n", at);
    const std::string_view line =
        head.substr(at, end == std::string_view::npos ? head.npos : end - at);
    if (line.empty()) break;
    const auto colon = line.find(':');
    if (colon != std::string_view::npos) {
      std::string value(line.substr(colon + 1));
      while (!value.empty() && value.front() == ' ') value.erase(value.begin());
      reply.headers[lower(std::string(line.substr(0, colon)))] = value;
    }
    if (end == std::string_view::npos) break;
    at = end + 2;
  }
  return reply;
}

// Writes `req` and reads the response from any connected stream, plain or TLS.
template <class Stream>
HttpReply exchange(Stream& stream, http::request<http::string_body>& req) {
  HttpReply reply;
  beast::error_code error;
  http::write(stream, req, error);
  // Even when the write failed (the server refused the body early), its answer may be there.
  beast::flat_buffer buffer;
  http::response_parser<http::string_body> parser;
  parser.body_limit(64 * 1024 * 1024);
  // A reply to HEAD says how long its body would be, and has none.
  parser.skip(req.method() == http::verb::head);
  beast::error_code read_error;
  http::read(stream, buffer, parser, read_error);
  if (read_error) {
    reply.status = 0;
    reply.body = "no reply: " + read_error.message() +
                 (error ? " (write: " + error.message() + ")" : std::string{});
    return reply;
  }
  auto res = parser.release();
  reply.status = res.result_int();
  reply.body = res.body();
  for (const auto& field : res) {
    reply.headers[lower(std::string(field.name_string()))] = std::string(field.value());
  }
  return reply;
}

std::string random_key() {
  std::random_device random;
  std::string bytes(16, '\0');
  for (auto& b : bytes) b = static_cast<char>(random() & 0xFF);
  return base64_encode(bytes);
}

}  // namespace

std::string HttpReply::error_code() const {
  try {
    return json().at("error").at("code").get<std::string>();
  } catch (const std::exception&) {
    return "<HTTP " + std::to_string(status) + " without an error code: " + body.substr(0, 200) +
           ">";
  }
}

HttpReply HttpClient::request(const std::string& method, const std::string& target,
                              const std::string& body,
                              const std::optional<std::string>& token_override) const {
  const std::string token = token_override.value_or(token_);
  return request_with_authorization(method, target, body, token.empty() ? "" : "Bearer " + token);
}

HttpReply HttpClient::request_with_authorization(const std::string& method,
                                                 const std::string& target, const std::string& body,
                                                 const std::string& authorization) const {
  HttpReply reply;
  try {
    boost::asio::io_context io;
    const tcp::endpoint server(boost::asio::ip::make_address("127.0.0.1"), port_);
    http::request<http::string_body> req{http::string_to_verb(method), target, 11};
    req.set(http::field::host, "127.0.0.1");
    if (!authorization.empty()) req.set(http::field::authorization, authorization);
    if (!body.empty()) {
      req.set(http::field::content_type, "application/json");
      req.body() = body;
    }
    req.prepare_payload();
    if (tls_ca_file_.empty()) {
      beast::tcp_stream stream(io);
      stream.expires_after(std::chrono::seconds(30));
      stream.connect(server);
      return exchange(stream, req);
    }
    namespace ssl = boost::asio::ssl;
    ssl::context context(ssl::context::tls_client);
    context.load_verify_file(tls_ca_file_.string());
    context.set_verify_mode(ssl::verify_peer);
    beast::ssl_stream<beast::tcp_stream> stream(io, context);
    X509_VERIFY_PARAM_set1_ip_asc(SSL_get0_param(stream.native_handle()), "127.0.0.1");
    beast::get_lowest_layer(stream).expires_after(std::chrono::seconds(30));
    beast::get_lowest_layer(stream).connect(server);
    stream.handshake(ssl::stream_base::client);
    reply = exchange(stream, req);
    // close_notify both ways, as a well-behaved client ends.
    beast::error_code ignored;
    stream.shutdown(ignored);
  } catch (const std::exception& error) {
    reply.status = 0;
    reply.body = std::string("request failed: ") + error.what();
  }
  return reply;
}

// ---------------------------------------------------------------------------------------------

RawConnection::RawConnection(std::uint16_t port, int receive_buffer_bytes) {
  fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
  if (fd_ < 0) return;
  if (receive_buffer_bytes > 0) {
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &receive_buffer_bytes, sizeof receive_buffer_bytes);
  }
  const int one = 1;
  ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  ::inet_pton(AF_INET, "127.0.0.1", &address.sin_addr);
  if (::connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    ::close(fd_);
    fd_ = -1;
  }
}

struct RawConnection::Tls {
  SSL_CTX* context = nullptr;
  SSL* ssl = nullptr;
  ~Tls() {
    if (ssl != nullptr) SSL_free(ssl);
    if (context != nullptr) SSL_CTX_free(context);
  }
};

RawConnection::~RawConnection() {
  tls_.reset();
  if (fd_ >= 0) ::close(fd_);
}

namespace {

// Waits for what OpenSSL said it wants (SSL_ERROR_WANT_READ or _WRITE); false on timeout.
bool wait_for(int fd, int ssl_error, std::chrono::steady_clock::time_point deadline) {
  pollfd poll_fd{fd, static_cast<short>(ssl_error == SSL_ERROR_WANT_WRITE ? POLLOUT : POLLIN), 0};
  return ::poll(&poll_fd, 1, remaining_ms(deadline)) > 0;
}

}  // namespace

bool RawConnection::start_tls(const std::filesystem::path& ca_file,
                              std::chrono::milliseconds timeout) {
  if (fd_ < 0) return false;
  // OpenSSL writes with write(): a server that closed must not end the test with SIGPIPE.
  std::signal(SIGPIPE, SIG_IGN);
  auto tls = std::make_unique<Tls>();
  tls->context = SSL_CTX_new(TLS_client_method());
  if (tls->context == nullptr ||
      SSL_CTX_load_verify_locations(tls->context, ca_file.c_str(), nullptr) != 1) {
    return false;
  }
  SSL_CTX_set_verify(tls->context, SSL_VERIFY_PEER, nullptr);
  tls->ssl = SSL_new(tls->context);
  if (tls->ssl == nullptr || SSL_set_fd(tls->ssl, fd_) != 1) return false;
  X509_VERIFY_PARAM_set1_ip_asc(SSL_get0_param(tls->ssl), "127.0.0.1");
  ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) | O_NONBLOCK);
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    const int result = SSL_connect(tls->ssl);
    if (result == 1) break;
    const int error = SSL_get_error(tls->ssl, result);
    if ((error != SSL_ERROR_WANT_READ && error != SSL_ERROR_WANT_WRITE) ||
        !wait_for(fd_, error, deadline)) {
      ERR_clear_error();
      return false;
    }
  }
  tls_ = std::move(tls);
  return true;
}

bool RawConnection::send(std::string_view bytes) {
  if (fd_ < 0) return false;
  if (tls_) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!bytes.empty()) {
      const int n = SSL_write(tls_->ssl, bytes.data(), static_cast<int>(bytes.size()));
      if (n > 0) {
        bytes.remove_prefix(static_cast<std::size_t>(n));
        continue;
      }
      const int error = SSL_get_error(tls_->ssl, n);
      if ((error != SSL_ERROR_WANT_READ && error != SSL_ERROR_WANT_WRITE) ||
          !wait_for(fd_, error, deadline)) {
        ERR_clear_error();
        return false;
      }
    }
    return true;
  }
  while (!bytes.empty()) {
    const ssize_t n = ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
  return true;
}

bool RawConnection::fill_tls(std::chrono::steady_clock::time_point deadline) {
  char chunk[65536];
  while (true) {
    const int n = SSL_read(tls_->ssl, chunk, sizeof chunk);
    if (n > 0) {
      buffer_.append(chunk, static_cast<std::size_t>(n));
      return true;
    }
    const int error = SSL_get_error(tls_->ssl, n);
    if (error == SSL_ERROR_WANT_READ || error == SSL_ERROR_WANT_WRITE) {
      if (!wait_for(fd_, error, deadline)) return false;
      continue;
    }
    // close_notify, a reset, or a connection cut short.
    ERR_clear_error();
    eof_ = true;
    return false;
  }
}

bool RawConnection::fill(std::chrono::steady_clock::time_point deadline) {
  if (fd_ < 0 || eof_) return false;
  if (tls_) return fill_tls(deadline);
  pollfd poll_fd{fd_, POLLIN, 0};
  const int ready = ::poll(&poll_fd, 1, remaining_ms(deadline));
  if (ready <= 0) return false;
  char chunk[65536];
  const ssize_t n = ::recv(fd_, chunk, sizeof chunk, 0);
  if (n <= 0) {
    eof_ = true;
    return false;
  }
  buffer_.append(chunk, static_cast<std::size_t>(n));
  return true;
}

std::optional<HttpReply> RawConnection::read_http_reply(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::size_t head_end = std::string::npos;
  while ((head_end = buffer_.find("\r\n\r\n")) == std::string::npos) {
    if (!fill(deadline)) return std::nullopt;
  }
  HttpReply reply = parse_response_head(std::string_view(buffer_).substr(0, head_end + 2));
  std::size_t body_bytes = 0;
  if (const auto length = reply.headers.find("content-length"); length != reply.headers.end()) {
    body_bytes = static_cast<std::size_t>(std::stoull(length->second));
  }
  const std::size_t total = head_end + 4 + body_bytes;
  while (buffer_.size() < total) {
    if (!fill(deadline)) return std::nullopt;
  }
  reply.body = buffer_.substr(head_end + 4, body_bytes);
  buffer_.erase(0, total);
  return reply;
}

std::string RawConnection::read_for(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline && !eof_) fill(deadline);
  std::string out;
  out.swap(buffer_);
  return out;
}

std::string RawConnection::receive_some(std::chrono::milliseconds timeout) {
  if (buffer_.empty()) fill(std::chrono::steady_clock::now() + timeout);
  std::string out;
  out.swap(buffer_);
  return out;
}

bool RawConnection::closed_by_peer(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!eof_ && std::chrono::steady_clock::now() < deadline) {
    fill(deadline);
    buffer_.clear();
  }
  return eof_;
}

// ---------------------------------------------------------------------------------------------

int WsFrame::close_code() const {
  if (opcode != WsOp::kClose || payload.size() < 2) return 0;
  return (static_cast<unsigned char>(payload[0]) << 8) | static_cast<unsigned char>(payload[1]);
}

std::string encode_client_frame(WsOp opcode, std::string_view payload, bool fin, bool masked) {
  std::string frame;
  frame.push_back(static_cast<char>((fin ? 0x80U : 0U) | static_cast<unsigned>(opcode)));
  const unsigned mask_bit = masked ? 0x80U : 0U;
  if (payload.size() < 126) {
    frame.push_back(static_cast<char>(mask_bit | payload.size()));
  } else if (payload.size() <= 0xFFFF) {
    frame.push_back(static_cast<char>(mask_bit | 126U));
    frame.push_back(static_cast<char>((payload.size() >> 8) & 0xFF));
    frame.push_back(static_cast<char>(payload.size() & 0xFF));
  } else {
    frame.push_back(static_cast<char>(mask_bit | 127U));
    for (int shift = 56; shift >= 0; shift -= 8) {
      frame.push_back(
          static_cast<char>((static_cast<std::uint64_t>(payload.size()) >> shift) & 0xFF));
    }
  }
  const unsigned char mask[4] = {0x12, 0x34, 0x56, 0x78};
  if (masked) frame.append(reinterpret_cast<const char*>(mask), 4);
  for (std::size_t i = 0; i < payload.size(); ++i) {
    const auto byte = static_cast<unsigned char>(payload[i]);
    frame.push_back(static_cast<char>(masked ? byte ^ mask[i % 4] : byte));
  }
  return frame;
}

WsClient::WsClient(std::uint16_t port, const std::string& token, int receive_buffer_bytes,
                   const std::string& target, const std::filesystem::path& tls_ca_file)
    : connection_(std::make_unique<RawConnection>(port, receive_buffer_bytes)) {
  if (!connection_->connected()) throw WsHandshakeError(0, "cannot connect");
  if (!tls_ca_file.empty() && !connection_->start_tls(tls_ca_file)) {
    throw WsHandshakeError(0, "TLS handshake failed");
  }
  const std::string path = target.empty() ? "/api/v1/stream?token=" + token : target;
  connection_->send("GET " + path +
                    " HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                    "Sec-WebSocket-Key: " +
                    random_key() + "\r\nSec-WebSocket-Version: 13\r\n\r\n");
  // The 101 has no body; read it byte-exactly so the frames after it stay in the buffer.
  const auto reply = connection_->read_http_reply(std::chrono::seconds(10));
  if (!reply) throw WsHandshakeError(0, "no answer to the upgrade");
  if (reply->status != 101) throw WsHandshakeError(reply->status, reply->body);
  pending_ = connection_->receive_some(std::chrono::milliseconds(0));
  const auto hello = read(std::chrono::seconds(10));
  if (!hello || !hello->text()) throw WsHandshakeError(101, "no hello frame");
  hello_ = hello->json();
}

std::optional<WsFrame> WsClient::parse_frame() {
  if (pending_.size() < 2) return std::nullopt;
  const auto* bytes = reinterpret_cast<const unsigned char*>(pending_.data());
  std::size_t header = 2;
  std::uint64_t length = bytes[1] & 0x7FU;
  if (length == 126) {
    if (pending_.size() < 4) return std::nullopt;
    header = 4;
    length = (std::uint64_t{bytes[2]} << 8) | bytes[3];
  } else if (length == 127) {
    if (pending_.size() < 10) return std::nullopt;
    header = 10;
    length = 0;
    for (int i = 2; i < 10; ++i) length = (length << 8) | bytes[i];
  }
  const bool masked = (bytes[1] & 0x80U) != 0;
  if (masked) header += 4;  // servers must not mask; tolerate it anyway
  if (pending_.size() < header + length) return std::nullopt;
  WsFrame frame;
  frame.opcode = static_cast<WsOp>(bytes[0] & 0x0FU);
  frame.payload = pending_.substr(header, static_cast<std::size_t>(length));
  if (masked) {
    for (std::size_t i = 0; i < frame.payload.size(); ++i) {
      frame.payload[i] = static_cast<char>(frame.payload[i] ^ bytes[header - 4 + i % 4]);
    }
  }
  pending_.erase(0, header + static_cast<std::size_t>(length));
  return frame;
}

std::optional<WsFrame> WsClient::read(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    while (auto frame = parse_frame()) {
      if (frame->opcode == WsOp::kPing) {
        connection_->send(encode_client_frame(WsOp::kPong, frame->payload));
        continue;
      }
      if (frame->opcode == WsOp::kClose) open_ = false;
      return frame;
    }
    if (!open_) return std::nullopt;
    std::string more = connection_->receive_some(std::chrono::milliseconds(remaining_ms(deadline)));
    if (more.empty()) {
      if (connection_->eof()) open_ = false;
      return std::nullopt;
    }
    pending_.append(more);
  }
}

std::optional<nlohmann::json> WsClient::read_until(const std::string& name,
                                                   std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    auto frame = read(left);
    if (!frame) return std::nullopt;
    if (!frame->text()) continue;
    auto message = nlohmann::json::parse(frame->payload, nullptr, false);
    if (!message.is_object()) continue;
    if (message.value("op", "") == name || message.value("topic", "") == name) return message;
  }
  return std::nullopt;
}

std::optional<WsFrame> WsClient::read_binary(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    auto frame = read(left);
    if (!frame) return std::nullopt;
    if (frame->binary()) return frame;
  }
  return std::nullopt;
}

std::vector<WsFrame> WsClient::read_all_for(std::chrono::milliseconds duration) {
  std::vector<WsFrame> frames;
  const auto deadline = std::chrono::steady_clock::now() + duration;
  while (std::chrono::steady_clock::now() < deadline) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    auto frame = read(left);
    if (!frame) {
      if (!open_) break;
      continue;
    }
    frames.push_back(std::move(*frame));
  }
  return frames;
}

int ws_upgrade_status(std::uint16_t port, const std::string& target) {
  RawConnection connection(port);
  if (!connection.connected()) return 0;
  connection.send("GET " + target +
                  " HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                  "Sec-WebSocket-Key: " +
                  random_key() + "\r\nSec-WebSocket-Version: 13\r\n\r\n");
  const auto reply = connection.read_http_reply(std::chrono::seconds(10));
  return reply ? reply->status : 0;
}

BinaryHeader parse_binary_header(const std::string& payload) {
  BinaryHeader header;
  if (payload.size() < 32) throw std::out_of_range("binary frame shorter than its header");
  header.magic = payload.substr(0, 4);
  header.topic_id = read_le<std::uint16_t>(payload, 4);
  header.header_bytes = read_le<std::uint16_t>(payload, 6);
  header.seq = read_le<std::uint64_t>(payload, 8);
  header.t = read_le<double>(payload, 16);
  header.wall_us = read_le<std::int64_t>(payload, 24);
  return header;
}

std::string base64_encode(std::string_view bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const std::uint32_t v = (static_cast<unsigned char>(bytes[i]) << 16) |
                            (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                            static_cast<unsigned char>(bytes[i + 2]);
    out.push_back(kAlphabet[(v >> 18) & 63]);
    out.push_back(kAlphabet[(v >> 12) & 63]);
    out.push_back(kAlphabet[(v >> 6) & 63]);
    out.push_back(kAlphabet[v & 63]);
  }
  if (i + 1 == bytes.size()) {
    const std::uint32_t v = static_cast<unsigned char>(bytes[i]) << 16;
    out.push_back(kAlphabet[(v >> 18) & 63]);
    out.push_back(kAlphabet[(v >> 12) & 63]);
    out += "==";
  } else if (i + 2 == bytes.size()) {
    const std::uint32_t v = (static_cast<unsigned char>(bytes[i]) << 16) |
                            (static_cast<unsigned char>(bytes[i + 1]) << 8);
    out.push_back(kAlphabet[(v >> 18) & 63]);
    out.push_back(kAlphabet[(v >> 12) & 63]);
    out.push_back(kAlphabet[(v >> 6) & 63]);
    out.push_back('=');
  }
  return out;
}

}  // namespace mobot::testing
