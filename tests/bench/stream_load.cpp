// mobot_stream_load: N WebSocket clients on loopback subscribe to a running mobotd's stream and
// timestamp every frame on receipt. Reports, per topic, frames received, frames lost (gaps in the
// per-topic seq), publish-to-receipt latency percentiles (from the frame's wall_us), and the
// server's CPU use over the measurement window (from /proc/PID/stat) when --pid is given.
//
// The clients are deliberately lean (raw sockets, one io thread, no JSON parsing of bulk data) so
// the tool measures the server rather than itself.
#include <CLI/CLI.hpp>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/read_until.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/streambuf.hpp>
#include <boost/asio/write.hpp>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace {

using boost::asio::ip::tcp;

std::int64_t wall_now_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

struct TopicStats {
  std::uint64_t frames = 0;
  std::uint64_t lost = 0;
  std::vector<std::int32_t> latency_us;
};

struct Totals {
  std::map<std::string, TopicStats> topics;
  bool measuring = false;
  int connected = 0;
  int failed = 0;
};

// Reads the numeric value after `key` in a JSON text (keys the server writes itself).
std::int64_t json_int_after(std::string_view text, std::string_view key) {
  const auto at = text.find(key);
  if (at == std::string_view::npos) return -1;
  return std::strtoll(text.data() + at + key.size(), nullptr, 10);
}

std::string json_topic(std::string_view text) {
  constexpr std::string_view kKey = R"("topic":")";
  const auto at = text.find(kKey);
  if (at == std::string_view::npos) return {};
  const auto start = at + kKey.size();
  return std::string(text.substr(start, text.find('"', start) - start));
}

class Client : public std::enable_shared_from_this<Client> {
 public:
  Client(boost::asio::io_context& io, Totals& totals, std::string request)
      : socket_(io), totals_(totals), request_(std::move(request)) {}

  void start(const tcp::endpoint& endpoint) {
    socket_.async_connect(endpoint, [self = shared_from_this()](boost::system::error_code error) {
      if (error) return self->fail("connect: " + error.message());
      self->socket_.set_option(tcp::no_delay(true));
      boost::asio::async_write(self->socket_, boost::asio::buffer(self->request_),
                               [self](boost::system::error_code write_error, std::size_t) {
                                 if (write_error) return self->fail("upgrade write");
                                 self->read_handshake();
                               });
    });
  }

 private:
  void fail(const std::string& why) {
    if (!failed_) {
      failed_ = true;
      ++totals_.failed;
      if (totals_.failed <= 3) std::cerr << "client failed: " << why << "\n";
    }
  }

  void read_handshake() {
    boost::asio::async_read_until(
        socket_, handshake_, "\r\n\r\n",
        [self = shared_from_this()](boost::system::error_code error, std::size_t bytes) {
          if (error) return self->fail("handshake: " + error.message());
          std::string head(boost::asio::buffers_begin(self->handshake_.data()),
                           boost::asio::buffers_begin(self->handshake_.data()) +
                               static_cast<std::ptrdiff_t>(bytes));
          if (head.rfind("HTTP/1.1 101", 0) != 0) return self->fail(head.substr(0, 40));
          self->handshake_.consume(bytes);
          // Bytes read past the handshake are the first frames.
          const auto extra = self->handshake_.size();
          self->buffer_.resize(extra);
          boost::asio::buffer_copy(boost::asio::buffer(self->buffer_), self->handshake_.data());
          ++self->totals_.connected;
          self->send_subscribe();
        });
  }

  void send_subscribe() {
    subscribe_frame_ = masked_text_frame(subscribe_json_);
    boost::asio::async_write(socket_, boost::asio::buffer(subscribe_frame_),
                             [self = shared_from_this()](boost::system::error_code error,
                                                         std::size_t) {
                               if (error) return self->fail("subscribe");
                               self->parse();
                               self->read_more();
                             });
  }

  static std::string masked_text_frame(const std::string& payload) {
    std::string frame;
    frame.push_back(static_cast<char>(0x81));
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

  void read_more() {
    const std::size_t used = buffer_.size();
    if (buffer_.capacity() - used < 65536) buffer_.reserve(used + 262144);
    buffer_.resize(buffer_.capacity());
    socket_.async_read_some(
        boost::asio::buffer(buffer_.data() + used, buffer_.size() - used),
        [self = shared_from_this(), used](boost::system::error_code error, std::size_t bytes) {
          if (error) {
            if (!self->stopped_) self->fail("read: " + error.message());
            return;
          }
          self->buffer_.resize(used + bytes);
          self->parse();
          self->read_more();
        });
  }

  void parse() {
    const std::int64_t now_us = wall_now_us();
    std::size_t offset = 0;
    while (true) {
      const std::size_t available = buffer_.size() - offset;
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
      if (available < header + length) break;
      on_frame(opcode, std::string_view(buffer_.data() + offset + header, length), now_us);
      offset += header + length;
    }
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(offset));
  }

  void on_frame(int opcode, std::string_view payload, std::int64_t now_us) {
    std::string topic;
    std::int64_t seq = -1;
    std::int64_t wall_us = -1;
    if (opcode == 0x2 && payload.size() >= 32 && payload.substr(0, 4) == "MBT1") {
      std::uint16_t topic_id = 0;
      std::uint64_t binary_seq = 0;
      std::memcpy(&topic_id, payload.data() + 4, 2);
      std::memcpy(&binary_seq, payload.data() + 8, 8);
      std::memcpy(&wall_us, payload.data() + 24, 8);
      static const std::array<const char*, 6> kNames{"?", "scan", "map", "cloud", "costmap",
                                                     "camera"};
      topic = topic_id < kNames.size() ? kNames[topic_id] : "?";
      seq = static_cast<std::int64_t>(binary_seq);
    } else if (opcode == 0x1) {
      topic = json_topic(payload);
      if (topic.empty()) return;  // hello, subscribed, pong
      seq = json_int_after(payload, R"("seq":)");
      wall_us = json_int_after(payload, R"("wall_us":)");
    } else {
      return;
    }
    auto& last = last_seq_[topic];
    if (totals_.measuring) {
      TopicStats& stats = totals_.topics[topic];
      ++stats.frames;
      if (last > 0 && seq > last + 1) stats.lost += static_cast<std::uint64_t>(seq - last - 1);
      stats.latency_us.push_back(static_cast<std::int32_t>(now_us - wall_us));
    }
    last = seq;
  }

 public:
  std::string subscribe_json_;
  bool stopped_ = false;

 private:
  tcp::socket socket_;
  Totals& totals_;
  std::string request_;
  boost::asio::streambuf handshake_;
  std::string subscribe_frame_;
  std::vector<char> buffer_;
  std::map<std::string, std::int64_t> last_seq_;
  bool failed_ = false;
};

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

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"mobot_stream_load: WebSocket fan-out load and latency of a running mobotd"};
  int port = 8080;
  std::string token;
  int clients = 100;
  double seconds = 10.0;
  double warmup_s = 2.0;
  int pid = 0;
  std::string topics = "pose,scan";
  std::string encoding = "binary";
  cli.add_option("--port", port)->required();
  cli.add_option("--token", token)->required();
  cli.add_option("--clients", clients)->check(CLI::Range(1, 20000));
  cli.add_option("--seconds", seconds, "measurement window");
  cli.add_option("--warmup", warmup_s, "seconds after all clients connected, before measuring");
  cli.add_option("--pid", pid, "mobotd's pid, to report its CPU use");
  cli.add_option("--topics", topics, "comma-separated topics");
  cli.add_option("--encoding", encoding)->check(CLI::IsMember({"binary", "json"}));
  CLI11_PARSE(cli, argc, argv);

  std::string topic_list;
  std::stringstream split(topics);
  for (std::string topic; std::getline(split, topic, ',');) {
    topic_list += (topic_list.empty() ? "\"" : ",\"") + topic + "\"";
  }
  const std::string subscribe =
      R"({"op":"subscribe","topics":[)" + topic_list + R"(],"encoding":")" + encoding + "\"}";
  const std::string upgrade = "GET /api/v1/stream?token=" + token +
                              " HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\n"
                              "Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
                              "Sec-WebSocket-Version: 13\r\n\r\n";

  boost::asio::io_context io;
  Totals totals;
  const tcp::endpoint endpoint(boost::asio::ip::make_address("127.0.0.1"),
                               static_cast<std::uint16_t>(port));
  std::vector<std::shared_ptr<Client>> all;
  for (int i = 0; i < clients; ++i) {
    auto client = std::make_shared<Client>(io, totals, upgrade);
    client->subscribe_json_ = subscribe;
    client->start(endpoint);
    all.push_back(client);
  }

  const auto run_for = [&io](double s) {
    io.restart();
    io.run_for(std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(s)));
  };
  const auto connect_deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (totals.connected + totals.failed < clients &&
         std::chrono::steady_clock::now() < connect_deadline) {
    run_for(0.1);
  }
  run_for(warmup_s);

  const double server_cpu_before = pid > 0 ? process_cpu_s(pid) : 0.0;
  const double own_cpu_before = process_cpu_s(static_cast<int>(getpid()));
  const auto started = std::chrono::steady_clock::now();
  totals.measuring = true;
  run_for(seconds);
  totals.measuring = false;
  const double elapsed_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const double server_cpu_s = pid > 0 ? process_cpu_s(pid) - server_cpu_before : 0.0;
  const double own_cpu_s = process_cpu_s(static_cast<int>(getpid())) - own_cpu_before;
  for (auto& client : all) client->stopped_ = true;

  std::cout << "clients " << clients << " connected " << totals.connected << " failed "
            << totals.failed << " window_s " << elapsed_s << "\n";
  bool ok = totals.failed == 0 && totals.connected == clients;
  for (auto& [topic, stats] : totals.topics) {
    const double rate_hz = static_cast<double>(stats.frames) / elapsed_s / clients;
    const double loss_pct =
        100.0 * static_cast<double>(stats.lost) / static_cast<double>(stats.frames + stats.lost);
    std::cout << "topic " << topic << " frames " << stats.frames << " per_client_hz " << rate_hz
              << " lost " << stats.lost << " loss_pct " << loss_pct << " latency_ms p50 "
              << percentile(stats.latency_us, 0.50) << " p99 " << percentile(stats.latency_us, 0.99)
              << " max " << percentile(stats.latency_us, 1.0) << "\n";
  }
  if (pid > 0) {
    std::cout << "server_cpu_pct_of_one_core " << 100.0 * server_cpu_s / elapsed_s << "\n";
  }
  std::cout << "load_tool_cpu_pct_of_one_core " << 100.0 * own_cpu_s / elapsed_s << "\n";
  return ok ? 0 : 1;
}
