#pragma once

#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace mobot::testing {

struct HttpReply {
  int status = 0;  // 0: no reply (connection error; `body` holds the reason)
  std::string body;
  std::map<std::string, std::string> headers;  // lower-case names
  nlohmann::json json() const { return nlohmann::json::parse(body); }
  // The `error.code` of an error body, or a description of what came instead.
  std::string error_code() const;
  std::string header(const std::string& lower_case_name) const {
    const auto it = headers.find(lower_case_name);
    return it == headers.end() ? std::string{} : it->second;
  }
};

// Blocking HTTP/1.1 client for tests: one connection per request. Never throws on a network error:
// the reply then has status 0.
class HttpClient {
 public:
  HttpClient(std::uint16_t port, std::string token) : port_(port), token_(std::move(token)) {}

  // The same client speaking https: it trusts the PEM certificate(s) in `ca_file` and checks that
  // the server's certificate is for 127.0.0.1; a handshake that fails is a reply with status 0.
  HttpClient over_tls(std::filesystem::path ca_file) const {
    HttpClient copy = *this;
    copy.tls_ca_file_ = std::move(ca_file);
    return copy;
  }

  HttpReply get(const std::string& target) const { return request("GET", target, ""); }
  HttpReply post(const std::string& target, const std::string& body) const {
    return request("POST", target, body);
  }
  HttpReply post(const std::string& target, const char* body) const {
    return request("POST", target, body);
  }
  HttpReply post(const std::string& target, const nlohmann::json& body) const {
    return request("POST", target, body.dump());
  }
  HttpReply put(const std::string& target, const nlohmann::json& body) const {
    return request("PUT", target, body.dump());
  }
  HttpReply del(const std::string& target) const { return request("DELETE", target, ""); }
  // `token_override`: "" sends no Authorization header at all.
  HttpReply request(const std::string& method, const std::string& target, const std::string& body,
                    const std::optional<std::string>& token_override = std::nullopt) const;
  // Sends `authorization` verbatim as the Authorization header (empty: none).
  HttpReply request_with_authorization(const std::string& method, const std::string& target,
                                       const std::string& body,
                                       const std::string& authorization) const;
  HttpClient with_token(std::string token) const {
    HttpClient copy = *this;
    copy.token_ = std::move(token);
    return copy;
  }
  std::uint16_t port() const { return port_; }
  const std::string& token() const { return token_; }

 private:
  std::uint16_t port_;
  std::string token_;
  std::filesystem::path tls_ca_file_;  // empty: plain http
};

// A plain TCP connection for protocol abuse: sends exactly the bytes given, reads what comes.
class RawConnection {
 public:
  // `receive_buffer_bytes` > 0 shrinks SO_RCVBUF before connecting (a slow reader).
  explicit RawConnection(std::uint16_t port, int receive_buffer_bytes = 0);
  ~RawConnection();
  RawConnection(const RawConnection&) = delete;
  RawConnection& operator=(const RawConnection&) = delete;

  bool connected() const { return fd_ >= 0; }
  // Speaks TLS from now on (the handshake done here, within the timeout), trusting `ca_file` and
  // checking the server's certificate is for 127.0.0.1. False when the handshake fails.
  bool start_tls(const std::filesystem::path& ca_file,
                 std::chrono::milliseconds timeout = std::chrono::seconds(10));
  // False when the peer has closed or reset the connection.
  bool send(std::string_view bytes);
  // Reads one HTTP response (header and a Content-Length body); nullopt on timeout or when the
  // connection closes first. Bytes after the response stay buffered for read_some().
  std::optional<HttpReply> read_http_reply(std::chrono::milliseconds timeout);
  // Everything that arrives within the timeout (returns early once the peer closes).
  std::string read_for(std::chrono::milliseconds timeout);
  // True when the peer closes (EOF or reset) within the timeout, discarding what it sends.
  bool closed_by_peer(std::chrono::milliseconds timeout);
  // Bytes already buffered plus what one read brings within the timeout (empty on timeout/EOF).
  std::string receive_some(std::chrono::milliseconds timeout);
  bool eof() const { return eof_; }
  int fd() const { return fd_; }

 private:
  // Appends what arrives within the timeout to buffer_; false on EOF/error or timeout.
  bool fill(std::chrono::steady_clock::time_point deadline);
  bool fill_tls(std::chrono::steady_clock::time_point deadline);

  struct Tls;
  int fd_ = -1;
  bool eof_ = false;
  std::string buffer_;
  std::unique_ptr<Tls> tls_;  // after start_tls()
};

enum class WsOp : std::uint8_t {
  kContinuation = 0x0,
  kText = 0x1,
  kBinary = 0x2,
  kClose = 0x8,
  kPing = 0x9,
  kPong = 0xA,
};

struct WsFrame {
  WsOp opcode = WsOp::kText;
  std::string payload;
  bool binary() const { return opcode == WsOp::kBinary; }
  bool text() const { return opcode == WsOp::kText; }
  nlohmann::json json() const { return nlohmann::json::parse(payload); }
  // For a close frame: its status code (0 when it carries none).
  int close_code() const;
};

// A client frame (masked, as RFC 6455 requires of clients unless `masked` is false).
std::string encode_client_frame(WsOp opcode, std::string_view payload, bool fin = true,
                                bool masked = true);

class WsHandshakeError : public std::runtime_error {
 public:
  WsHandshakeError(int status, std::string body)
      : std::runtime_error("WebSocket upgrade refused with HTTP " + std::to_string(status) + ": " +
                           body),
        status_(status),
        body_(std::move(body)) {}
  int status() const { return status_; }
  const std::string& body() const { return body_; }

 private:
  int status_;
  std::string body_;
};

// A WebSocket client of /api/v1/stream written on a raw socket, so that a read can time out
// without breaking the connection and every frame (text, binary, close) is visible as sent.
class WsClient {
 public:
  // Connects and upgrades; throws WsHandshakeError when the server answers other than 101.
  // `target`: empty means /api/v1/stream?token=TOKEN. `tls_ca_file`: not empty, wss trusting it.
  WsClient(std::uint16_t port, const std::string& token, int receive_buffer_bytes = 0,
           const std::string& target = "", const std::filesystem::path& tls_ca_file = {});

  void send(const nlohmann::json& message) { send_text(message.dump()); }
  void send_text(std::string_view text) { send_raw(encode_client_frame(WsOp::kText, text)); }
  bool send_raw(std::string_view bytes) { return connection_->send(bytes); }

  // The next frame (server pings are answered and skipped), or nullopt after the timeout or when
  // the connection closed.
  std::optional<WsFrame> read(std::chrono::milliseconds timeout = std::chrono::seconds(5));
  // The next JSON text frame whose "op" or "topic" equals `name`, skipping others.
  std::optional<nlohmann::json> read_until(
      const std::string& name, std::chrono::milliseconds timeout = std::chrono::seconds(5));
  // The next binary frame, skipping text frames.
  std::optional<WsFrame> read_binary(std::chrono::milliseconds timeout = std::chrono::seconds(5));
  // Reads and discards frames for the given time; returns them.
  std::vector<WsFrame> read_all_for(std::chrono::milliseconds duration);
  // False after a close frame arrived or the connection ended.
  bool is_open() const { return open_; }
  // The hello the server sent first (read by the constructor).
  const nlohmann::json& hello() const { return hello_; }
  int fd() const { return connection_->fd(); }

 private:
  std::optional<WsFrame> parse_frame();

  std::unique_ptr<RawConnection> connection_;
  std::string pending_;
  bool open_ = true;
  nlohmann::json hello_;
};

// Sends a WebSocket upgrade request for `target` and returns the HTTP status of the answer
// (101 when accepted).
int ws_upgrade_status(std::uint16_t port, const std::string& target);

// Fields of a binary stream frame (README "Binary frames").
struct BinaryHeader {
  std::string magic;
  std::uint16_t topic_id = 0;
  std::uint16_t header_bytes = 0;
  std::uint64_t seq = 0;
  double t = 0.0;
  std::int64_t wall_us = 0;
};
BinaryHeader parse_binary_header(const std::string& payload);

template <class T>
T read_le(const std::string& bytes, std::size_t offset) {
  if (offset + sizeof(T) > bytes.size()) throw std::out_of_range("read past the end of a frame");
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return value;
}

std::string base64_encode(std::string_view bytes);

}  // namespace mobot::testing
