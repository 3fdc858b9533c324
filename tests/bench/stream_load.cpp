// mobot_stream_load: N WebSocket clients on loopback subscribe to a running mobotd's stream and
// timestamp every frame on receipt. Reports, per topic, frames received, frames lost (gaps in the
// per-topic seq), publish-to-receipt latency percentiles (from the frame's wall_us, stamped by the
// server when the frame was published), and the server's CPU use over the measurement window (from
// /proc/PID/stat) when --pid is given.
//
// The clients are deliberately lean so the tool measures the server rather than itself: plain
// sockets on a level-triggered epoll per reader thread, one recv per readiness into a buffer that
// is allocated once, the receipt time taken as soon as that recv returns, and no JSON parsing of
// bulk data. Every frame of one recv shares its receipt time: that is when they reached the client.
#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

namespace {

// Topics the tool can attribute a frame to; the binary topic ids of the README map onto the same
// slots by name.
constexpr std::array<std::string_view, 12> kTopicNames{"?",     "pose",  "odom",    "scan",
                                                       "sonar", "map",   "status",  "events",
                                                       "truth", "cloud", "costmap", "camera"};
constexpr std::size_t kTopicSlots = kTopicNames.size();
constexpr std::array<std::size_t, 6> kBinaryTopicSlot{0, 3, 5, 9, 10, 11};  // by binary topic id

constexpr std::size_t kInitialBuffer = 256 * 1024;

std::int64_t wall_now_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::size_t slot_of(std::string_view name) {
  for (std::size_t i = 1; i < kTopicSlots; ++i) {
    if (kTopicNames[i] == name) return i;
  }
  return 0;
}

struct TopicStats {
  std::uint64_t frames = 0;
  std::uint64_t lost = 0;
  std::uint64_t bytes = 0;  // frame payloads, headers included
  std::vector<std::int32_t> latency_us;
};

// The publish-to-receipt latencies of one client, per topic: a target holds for every client, not
// only for all of them together.
using ClientLatencies = std::array<std::vector<std::int32_t>, kTopicSlots>;

// Reads the numeric value after `key` in a JSON text (keys the server writes itself).
std::int64_t json_int_after(std::string_view text, std::string_view key) {
  const auto at = text.find(key);
  if (at == std::string_view::npos) return -1;
  return std::strtoll(text.data() + at + key.size(), nullptr, 10);
}

std::string_view json_topic(std::string_view text) {
  constexpr std::string_view kKey = R"("topic":")";
  const auto at = text.find(kKey);
  if (at == std::string_view::npos) return {};
  const auto start = at + kKey.size();
  const auto end = text.find('"', start);
  if (end == std::string_view::npos) return {};
  return text.substr(start, end - start);
}

std::string masked_frame(unsigned opcode, std::string_view payload) {
  std::string frame;
  frame.push_back(static_cast<char>(0x80 | opcode));
  if (payload.size() < 126) {
    frame.push_back(static_cast<char>(0x80 | payload.size()));
  } else {
    frame.push_back(static_cast<char>(0x80 | 126));
    frame.push_back(static_cast<char>((payload.size() >> 8) & 0xFF));
    frame.push_back(static_cast<char>(payload.size() & 0xFF));
  }
  frame.append(4, '\0');  // a zero mask leaves the payload as it is
  frame += payload;
  return frame;
}

std::string masked_text_frame(const std::string& payload) { return masked_frame(0x1, payload); }

bool send_all(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t sent = ::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    if (sent < 0 && errno == EINTR) continue;
    if (sent <= 0) return false;
    bytes.remove_prefix(static_cast<std::size_t>(sent));
  }
  return true;
}

// One stream client: its socket, the bytes of a frame not yet complete, the last seq per topic.
class Client {
 public:
  explicit Client(int fd) : fd_(fd), buffer_(kInitialBuffer) {}
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;
  ~Client() {
    if (fd_ >= 0) ::close(fd_);
  }

  int fd() const { return fd_; }
  // A small frame of the client's (a pong), written whole or not at all: the socket's send buffer
  // always has room for a few bytes unless the server stopped reading, and then nothing matters.
  void send(const std::string& frame) { ::send(fd_, frame.data(), frame.size(), MSG_NOSIGNAL); }

  // Blocking HTTP upgrade and subscription, before the socket joins a reader's epoll.
  std::optional<std::string> handshake(const std::string& upgrade, const std::string& subscribe) {
    if (!send_all(fd_, upgrade)) return "upgrade write: " + std::string(std::strerror(errno));
    std::size_t head_end = std::string_view::npos;
    while (head_end == std::string_view::npos) {
      if (used_ == buffer_.size()) return "handshake too long";
      const ssize_t got = ::recv(fd_, buffer_.data() + used_, buffer_.size() - used_, 0);
      if (got <= 0) return "handshake: connection closed";
      used_ += static_cast<std::size_t>(got);
      head_end = std::string_view(buffer_.data(), used_).find("\r\n\r\n");
    }
    const std::string_view head(buffer_.data(), head_end);
    if (head.rfind("HTTP/1.1 101", 0) != 0) return std::string(head.substr(0, 40));
    // Bytes read past the handshake are the first frames.
    consume(head_end + 4);
    if (!send_all(fd_, masked_text_frame(subscribe))) return "subscribe write";
    return std::nullopt;
  }

  // One recv; false when the connection is gone.
  template <typename OnFrame>
  bool read(OnFrame&& on_frame) {
    if (used_ == buffer_.size()) buffer_.resize(buffer_.size() * 2);  // a frame larger than it
    const ssize_t got = ::recv(fd_, buffer_.data() + used_, buffer_.size() - used_, 0);
    if (got < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return true;
    if (got <= 0) return false;
    const std::int64_t now_us = wall_now_us();
    used_ += static_cast<std::size_t>(got);
    parse(now_us, on_frame);
    return true;
  }

  std::array<std::int64_t, kTopicSlots>& last_seq() { return last_seq_; }
  ClientLatencies& latency_us() { return latency_us_; }

 private:
  void consume(std::size_t bytes) {
    std::memmove(buffer_.data(), buffer_.data() + bytes, used_ - bytes);
    used_ -= bytes;
  }

  template <typename OnFrame>
  void parse(std::int64_t now_us, OnFrame& on_frame) {
    std::size_t offset = 0;
    while (true) {
      const std::size_t available = used_ - offset;
      if (available < 2) break;
      const auto* p = reinterpret_cast<const unsigned char*>(buffer_.data() + offset);
      const int opcode = p[0] & 0x0F;
      std::uint64_t length = p[1] & 0x7F;
      std::size_t header = 2;
      if (length == 126) {
        if (available < 4) break;
        length = (std::uint64_t{p[2]} << 8) | p[3];
        header = 4;
      } else if (length == 127) {
        if (available < 10) break;
        length = 0;
        for (int i = 0; i < 8; ++i) length = (length << 8) | p[2 + i];
        header = 10;
      }
      if (available < header + length) {
        // Make room for a frame that does not fit at all.
        if (header + length > buffer_.size()) buffer_.resize(header + length);
        break;
      }
      on_frame(*this, opcode,
               std::string_view(buffer_.data() + offset + header, static_cast<std::size_t>(length)),
               now_us);
      offset += header + static_cast<std::size_t>(length);
    }
    if (offset > 0) consume(offset);
  }

  int fd_;
  std::vector<char> buffer_;  // sized once; only a frame larger than it grows it
  std::size_t used_ = 0;
  std::array<std::int64_t, kTopicSlots> last_seq_{};
  ClientLatencies latency_us_;
};

// A thread with its own epoll and its share of the clients.
class Reader {
 public:
  Reader(const std::atomic<bool>& measuring, const std::atomic<bool>& stopping)
      : measuring_(measuring), stopping_(stopping), epoll_fd_(::epoll_create1(0)) {}
  ~Reader() { ::close(epoll_fd_); }

  void add(std::unique_ptr<Client> client) {
    epoll_event event{};
    event.events = EPOLLIN;
    event.data.ptr = client.get();
    ::epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, client->fd(), &event);
    clients_.push_back(std::move(client));
  }

  // Room for each client's latencies of a topic, so that no reallocation stalls the reader while
  // measuring.
  void reserve(std::size_t slot, std::size_t frames_per_client) {
    for (auto& client : clients_) client->latency_us()[slot].reserve(frames_per_client);
  }

  void start() {
    thread_ = std::thread([this] { run(); });
  }
  void join() { thread_.join(); }

  std::array<TopicStats, kTopicSlots>& stats() { return stats_; }
  const std::vector<std::unique_ptr<Client>>& clients() const { return clients_; }
  int failed() const { return failed_; }

 private:
  void run() {
    std::array<epoll_event, 256> events{};
    while (!stopping_.load(std::memory_order_relaxed)) {
      const int ready = ::epoll_wait(epoll_fd_, events.data(), static_cast<int>(events.size()), 20);
      for (int i = 0; i < ready; ++i) {
        auto* client = static_cast<Client*>(events[static_cast<std::size_t>(i)].data.ptr);
        if (!client->read([this](Client& c, int opcode, std::string_view payload,
                                 std::int64_t now_us) { on_frame(c, opcode, payload, now_us); })) {
          ::epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, client->fd(), nullptr);
          if (!stopping_.load()) ++failed_;
          if (failed_ <= 3 && !stopping_.load()) std::cerr << "client failed: connection closed\n";
        }
      }
    }
  }

  void on_frame(Client& client, int opcode, std::string_view payload, std::int64_t now_us) {
    if (opcode == 0x9) {
      // RFC 6455 5.5.2: the server's pings (its round trip, its liveness check) get their pong,
      // or it closes a client that seems gone after 45 s.
      client.send(masked_frame(0xA, payload));
      return;
    }
    std::size_t slot = 0;
    std::int64_t seq = -1;
    std::int64_t wall_us = -1;
    if (opcode == 0x2 && payload.size() >= 32 && payload.substr(0, 4) == "MBT1") {
      std::uint16_t topic_id = 0;
      std::uint64_t binary_seq = 0;
      std::memcpy(&topic_id, payload.data() + 4, 2);
      std::memcpy(&binary_seq, payload.data() + 8, 8);
      std::memcpy(&wall_us, payload.data() + 24, 8);
      slot = topic_id < kBinaryTopicSlot.size() ? kBinaryTopicSlot[topic_id] : 0;
      seq = static_cast<std::int64_t>(binary_seq);
    } else if (opcode == 0x1) {
      const std::string_view topic = json_topic(payload);
      if (topic.empty()) return;  // hello, subscribed, pong
      slot = slot_of(topic);
      seq = json_int_after(payload, R"("seq":)");
      wall_us = json_int_after(payload, R"("wall_us":)");
    } else {
      return;
    }
    auto& last = client.last_seq()[slot];
    if (measuring_.load(std::memory_order_relaxed)) {
      TopicStats& stats = stats_[slot];
      ++stats.frames;
      stats.bytes += payload.size();
      if (last > 0 && seq > last + 1) stats.lost += static_cast<std::uint64_t>(seq - last - 1);
      client.latency_us()[slot].push_back(static_cast<std::int32_t>(now_us - wall_us));
    }
    last = seq;
  }

  const std::atomic<bool>& measuring_;
  const std::atomic<bool>& stopping_;
  int epoll_fd_;
  std::vector<std::unique_ptr<Client>> clients_;
  std::array<TopicStats, kTopicSlots> stats_;
  int failed_ = 0;
  std::thread thread_;
};

// A connected TCP socket to 127.0.0.1:port, or -1.
int connect_loopback(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return -1;
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    ::close(fd);
    return -1;
  }
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  return fd;
}

// utime + stime of a process in seconds.
double process_cpu_s(int pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
  const auto close = text.rfind(')');
  if (close == std::string::npos) return -1.0;
  std::istringstream fields(text.substr(close + 2));
  std::string field;
  double ticks = 0.0;
  for (int index = 3; fields >> field; ++index) {
    if (index == 14 || index == 15) ticks += std::stod(field);
    if (index == 15) break;
  }
  return ticks / static_cast<double>(sysconf(_SC_CLK_TCK));
}

double percentile(std::vector<std::int32_t>& values, double p) {
  if (values.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(p * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k] / 1000.0;
}

void sleep_s(double seconds) {
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
}

// One blocking HTTP/1.1 request on a keep-alive socket: the status and the body, or nullopt when
// the connection failed.
std::optional<std::pair<int, std::string>> http_get(int fd, const std::string& request) {
  if (::send(fd, request.data(), request.size(), MSG_NOSIGNAL) !=
      static_cast<ssize_t>(request.size())) {
    return std::nullopt;
  }
  std::string reply;
  std::array<char, 8192> chunk{};
  std::size_t header_end = std::string::npos;
  while ((header_end = reply.find("\r\n\r\n")) == std::string::npos) {
    const ssize_t got = ::recv(fd, chunk.data(), chunk.size(), 0);
    if (got <= 0) return std::nullopt;
    reply.append(chunk.data(), static_cast<std::size_t>(got));
  }
  const int status = reply.size() > 12 ? std::atoi(reply.c_str() + 9) : 0;
  std::size_t length = 0;
  const auto field = reply.find("Content-Length: ");
  if (field != std::string::npos && field < header_end) length = std::stoul(reply.substr(field + 16));
  while (reply.size() < header_end + 4 + length) {
    const ssize_t got = ::recv(fd, chunk.data(), chunk.size(), 0);
    if (got <= 0) return std::nullopt;
    reply.append(chunk.data(), static_cast<std::size_t>(got));
  }
  return std::make_pair(status, reply.substr(header_end + 4, length));
}

// A REST client polling GET /api/v1/robot at `rate_hz` on one keep-alive connection, as a
// dashboard or another service does: how many requests it made, how many failed (not 200, or the
// connection lost), and their latencies while measuring. `phase` (a fraction of the period) is
// when in each period it asks: clients that do not know of each other do not ask in step.
class RestPoller {
 public:
  RestPoller(int port, const std::string& token, double rate_hz, double phase,
             const std::atomic<bool>& measuring, const std::atomic<bool>& stopping)
      : port_(port),
        request_("GET /api/v1/robot HTTP/1.1\r\nHost: 127.0.0.1\r\nAuthorization: Bearer " + token +
                 "\r\n\r\n"),
        period_(1.0 / rate_hz),
        phase_(phase * period_),
        measuring_(measuring),
        stopping_(stopping) {}

  void start() { thread_ = std::thread([this] { run(); }); }
  void join() { thread_.join(); }
  std::uint64_t requests() const { return requests_; }
  std::uint64_t errors() const { return errors_; }
  std::vector<std::int32_t>& latency_us() { return latency_us_; }

 private:
  void run() {
    int fd = connect_loopback(port_);
    auto next = std::chrono::steady_clock::now() +
                std::chrono::duration_cast<std::chrono::steady_clock::duration>(phase_);
    while (!stopping_) {
      next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period_);
      std::this_thread::sleep_until(next);
      if (fd < 0) fd = connect_loopback(port_);
      const bool measured = measuring_;
      const auto sent = std::chrono::steady_clock::now();
      const auto reply = fd >= 0 ? http_get(fd, request_) : std::nullopt;
      if (!measured) continue;
      ++requests_;
      if (!reply || reply->first != 200) {
        ++errors_;
        if (!reply && fd >= 0) {
          ::close(fd);
          fd = -1;
        }
        continue;
      }
      latency_us_.push_back(static_cast<std::int32_t>(
          std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() -
                                                                sent)
              .count()));
    }
    if (fd >= 0) ::close(fd);
  }

  int port_;
  std::string request_;
  std::chrono::duration<double> period_;
  std::chrono::duration<double> phase_;
  const std::atomic<bool>& measuring_;
  const std::atomic<bool>& stopping_;
  std::uint64_t requests_ = 0;
  std::uint64_t errors_ = 0;
  std::vector<std::int32_t> latency_us_;
  std::thread thread_;
};

// A counter of the server's /metrics (-1 when it cannot be read).
double server_metric(int port, const std::string& token, const std::string& name) {
  const int fd = connect_loopback(port);
  if (fd < 0) return -1.0;
  const auto reply = http_get(
      fd, "GET /metrics HTTP/1.1\r\nHost: 127.0.0.1\r\nAuthorization: Bearer " + token + "\r\n\r\n");
  ::close(fd);
  if (!reply || reply->first != 200) return -1.0;
  const auto at = reply->second.find("\n" + name + " ");
  return at == std::string::npos ? -1.0 : std::stod(reply->second.substr(at + name.size() + 2));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"mobot_stream_load: WebSocket fan-out load and latency of a running mobotd"};
  int port = 8080;
  std::string token;
  int clients = 100;
  int threads = 1;
  double seconds = 10.0;
  double warmup_s = 2.0;
  int pid = 0;
  std::string topics = "pose,scan";
  std::string encoding = "binary";
  int camera_quality = 0;
  int rest_clients = 0;
  double rest_hz = 20.0;
  bool rest_in_step = false;
  cli.add_option("--port", port)->required();
  cli.add_option("--token", token)->required();
  cli.add_option("--clients", clients)->check(CLI::Range(1, 20000));
  cli.add_option("--threads", threads,
                 "reader threads, each with its own epoll and a share of the clients")
      ->check(CLI::Range(1, 64));
  cli.add_option("--seconds", seconds, "measurement window");
  cli.add_option("--warmup", warmup_s, "seconds after all clients connected, before measuring");
  cli.add_option("--pid", pid, "mobotd's pid, to report its CPU use");
  cli.add_option("--topics", topics, "comma-separated topics");
  cli.add_option("--encoding", encoding)->check(CLI::IsMember({"binary", "json"}));
  cli.add_option("--camera-quality", camera_quality,
                 "the JPEG quality cap of the camera frames (camera_quality), 0: the camera's")
      ->check(CLI::Range(0, 100));
  cli.add_option("--rest-clients", rest_clients,
                 "REST clients polling GET /api/v1/robot meanwhile, each on its own connection")
      ->check(CLI::Range(0, 5000));
  cli.add_option("--rest-hz", rest_hz, "requests a second of each REST client")
      ->check(CLI::Range(0.1, 200.0));
  cli.add_flag("--rest-in-step", rest_in_step,
               "all REST clients ask at the same instant of each period (a burst), instead of "
               "spread evenly over it");
  CLI11_PARSE(cli, argc, argv);

  std::string topic_list;
  std::stringstream split(topics);
  for (std::string topic; std::getline(split, topic, ',');) {
    topic_list += (topic_list.empty() ? "\"" : ",\"") + topic + "\"";
  }
  const std::string quality =
      camera_quality > 0 ? R"(,"camera_quality":)" + std::to_string(camera_quality) : "";
  const std::string subscribe = R"({"op":"subscribe","topics":[)" + topic_list +
                                R"(],"encoding":")" + encoding + "\"" + quality + "}";
  const std::string upgrade =
      "GET /api/v1/stream?token=" + token +
      " HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\n"
      "Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
      "Sec-WebSocket-Version: 13\r\n\r\n";

  std::atomic<bool> measuring{false};
  std::atomic<bool> stopping{false};
  std::vector<std::unique_ptr<Reader>> readers;
  for (int i = 0; i < threads; ++i) {
    readers.push_back(std::make_unique<Reader>(measuring, stopping));
  }

  int connected = 0;
  int failed = 0;
  for (int i = 0; i < clients; ++i) {
    const int fd = connect_loopback(port);
    if (fd < 0) {
      if (++failed <= 3) std::cerr << "client failed: connect: " << std::strerror(errno) << "\n";
      continue;
    }
    auto client = std::make_unique<Client>(fd);
    if (const auto error = client->handshake(upgrade, subscribe)) {
      if (++failed <= 3) std::cerr << "client failed: " << *error << "\n";
      continue;
    }
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
    readers[static_cast<std::size_t>(i % threads)]->add(std::move(client));
    ++connected;
  }
  // Up to 60 Hz per topic and client, with a margin.
  const auto expected_frames = static_cast<std::size_t>(1.25 * 60.0 * (seconds + 1.0));
  std::stringstream names(topics);
  for (std::string topic; std::getline(names, topic, ',');) {
    for (auto& reader : readers) reader->reserve(slot_of(topic), expected_frames);
  }
  for (auto& reader : readers) reader->start();
  std::vector<std::unique_ptr<RestPoller>> pollers;
  for (int i = 0; i < rest_clients; ++i) {
    const double phase = rest_in_step ? 0.0 : static_cast<double>(i) / rest_clients;
    pollers.push_back(
        std::make_unique<RestPoller>(port, token, rest_hz, phase, measuring, stopping));
    pollers.back()->start();
  }
  sleep_s(warmup_s);
  const double late_ticks_before = server_metric(port, token, "mobot_control_late_ticks_total");

  const double server_cpu_before = pid > 0 ? process_cpu_s(pid) : 0.0;
  const double own_cpu_before = process_cpu_s(static_cast<int>(getpid()));
  const auto started = std::chrono::steady_clock::now();
  measuring = true;
  sleep_s(seconds);
  measuring = false;
  const double elapsed_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const double server_cpu_s = pid > 0 ? process_cpu_s(pid) - server_cpu_before : 0.0;
  const double own_cpu_s = process_cpu_s(static_cast<int>(getpid())) - own_cpu_before;
  const double late_ticks = server_metric(port, token, "mobot_control_late_ticks_total") -
                            late_ticks_before;
  const double lateness_p99_s =
      server_metric(port, token, "mobot_control_tick_lateness_seconds_p99");
  stopping = true;
  for (auto& reader : readers) reader->join();
  std::uint64_t rest_requests = 0;
  std::uint64_t rest_errors = 0;
  std::vector<std::int32_t> rest_latency_us;
  for (auto& poller : pollers) {
    poller->join();
    rest_requests += poller->requests();
    rest_errors += poller->errors();
    rest_latency_us.insert(rest_latency_us.end(), poller->latency_us().begin(),
                           poller->latency_us().end());
  }

  std::array<TopicStats, kTopicSlots> totals;
  // Per topic, each client's p99 (ms), for the worst client's.
  std::array<std::vector<std::int32_t>, kTopicSlots> client_p99_us;
  for (auto& reader : readers) {
    failed += reader->failed();
    for (std::size_t slot = 0; slot < kTopicSlots; ++slot) {
      auto& from = reader->stats()[slot];
      totals[slot].frames += from.frames;
      totals[slot].lost += from.lost;
      totals[slot].bytes += from.bytes;
    }
    for (const auto& client : reader->clients()) {
      for (std::size_t slot = 0; slot < kTopicSlots; ++slot) {
        auto& latencies = client->latency_us()[slot];
        if (latencies.empty()) continue;
        totals[slot].latency_us.insert(totals[slot].latency_us.end(), latencies.begin(),
                                       latencies.end());
        client_p99_us[slot].push_back(
            static_cast<std::int32_t>(std::lround(percentile(latencies, 0.99) * 1e3)));
      }
    }
  }

  std::cout << "clients " << clients << " connected " << connected << " failed " << failed
            << " window_s " << elapsed_s << " reader_threads " << threads << "\n";
  const bool ok = failed == 0 && connected == clients;
  for (std::size_t slot = 0; slot < kTopicSlots; ++slot) {
    TopicStats& stats = totals[slot];
    if (stats.frames == 0) continue;
    const double rate_hz = static_cast<double>(stats.frames) / elapsed_s / clients;
    const double loss_pct =
        100.0 * static_cast<double>(stats.lost) / static_cast<double>(stats.frames + stats.lost);
    std::cout << "topic " << kTopicNames[slot] << " frames " << stats.frames << " per_client_hz "
              << rate_hz << " lost " << stats.lost << " loss_pct " << loss_pct << " latency_ms p50 "
              << percentile(stats.latency_us, 0.50) << " p99 " << percentile(stats.latency_us, 0.99)
              << " max " << percentile(stats.latency_us, 1.0) << " worst_client_p99 "
              << percentile(client_p99_us[slot], 1.0) << " mean_frame_kb "
              << static_cast<double>(stats.bytes) / static_cast<double>(stats.frames) / 1024.0
              << "\n";
  }
  if (pid > 0) {
    std::cout << "server_cpu_pct_of_one_core " << 100.0 * server_cpu_s / elapsed_s << "\n";
  }
  std::cout << "load_tool_cpu_pct_of_one_core " << 100.0 * own_cpu_s / elapsed_s << "\n";
  if (rest_clients > 0) {
    std::cout << "rest clients " << rest_clients << " requests " << rest_requests << " errors "
              << rest_errors << " latency_ms p50 " << percentile(rest_latency_us, 0.50) << " p99 "
              << percentile(rest_latency_us, 0.99) << " max " << percentile(rest_latency_us, 1.0)
              << "\n";
  }
  std::cout << "control late_ticks " << late_ticks << " tick_lateness_p99_ms "
            << lateness_p99_s * 1e3 << "\n";
  return ok && rest_errors == 0 ? 0 : 1;
}
