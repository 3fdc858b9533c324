// Stream sessions over real loopback sockets for the API's unit tests: a blocking WebSocket client
// on the test thread, and a fixture whose sessions run on two io threads against the fake ports.
#pragma once

#include <gtest/gtest.h>
#include <sys/socket.h>

#include <array>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/write.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "api/stream_hub.h"
#include "api/stream_session.h"
#include "client_frames.h"
#include "fake_ports.h"

namespace mobot::api::test {

struct Frame {
  unsigned opcode = 0;
  std::string payload;
  bool fin = true;

  // A close frame's status code, or 0 when it has none.
  unsigned close_code() const {
    if (payload.size() < 2) return 0;
    return (static_cast<unsigned char>(payload[0]) << 8) | static_cast<unsigned char>(payload[1]);
  }
};

// A blocking WebSocket client on the test thread.
class Client {
 public:
  Client(boost::asio::io_context& io, const boost::asio::ip::tcp::endpoint& server,
         int receive_buffer = 0)
      : socket_(io) {
    socket_.open(boost::asio::ip::tcp::v4());
    if (receive_buffer > 0) {
      socket_.set_option(boost::asio::socket_base::receive_buffer_size(receive_buffer));
    }
    socket_.connect(server);
    const timeval timeout{5, 0};
    ::setsockopt(socket_.native_handle(), SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  }

  void send_text(const std::string& text, bool masked = true) { send(0x1, text, masked); }
  void send_pong(const std::string& payload) { send(0xA, payload, true); }

  // One short frame (below 126 bytes) with FIN set.
  void send(unsigned opcode, const std::string& payload, bool masked) {
    std::string frame;
    frame.push_back(static_cast<char>(0x80U | opcode));
    frame.push_back(static_cast<char>((masked ? 0x80U : 0x00U) | payload.size()));
    if (masked) frame.append(4, '\0');  // a zero mask leaves the payload as it is
    frame += payload;
    send_raw(frame);
  }

  // Bytes as they are, in one write.
  void send_raw(std::string_view bytes) {
    boost::asio::write(socket_, boost::asio::buffer(bytes.data(), bytes.size()));
  }

  // The next frame, or nullopt on a closed connection or after the 5 s receive time-out.
  std::optional<Frame> read() {
    std::array<unsigned char, 10> header{};
    if (!read_exactly(header.data(), 2)) return std::nullopt;
    std::uint64_t length = header[1] & 0x7FU;
    if (length == 126 || length == 127) {
      const std::size_t extra = length == 126 ? 2 : 8;
      if (!read_exactly(header.data() + 2, extra)) return std::nullopt;
      length = 0;
      for (std::size_t i = 0; i < extra; ++i) length = (length << 8) | header[2 + i];
    }
    Frame frame{header[0] & 0x0FU, std::string(length, '\0'), (header[0] & 0x80U) != 0};
    if (!read_exactly(frame.payload.data(), frame.payload.size())) return std::nullopt;
    return frame;
  }

  // Reads until a text frame containing `text`.
  bool read_until(const std::string& text) {
    while (auto frame = read()) {
      if (frame->payload.find(text) != std::string::npos) return true;
    }
    return false;
  }

  // The frames up to the server's close frame (the last one, if it came) and the end of the
  // connection.
  std::vector<Frame> read_to_end() {
    std::vector<Frame> frames;
    while (auto frame = read()) frames.push_back(std::move(*frame));
    return frames;
  }

  // The server closed the TCP connection (not a receive time-out): the next read sees its end.
  bool connection_ended() {
    std::array<char, 1> byte{};
    boost::system::error_code error;
    socket_.read_some(boost::asio::buffer(byte), error);
    return error == boost::asio::error::eof || error == boost::asio::error::connection_reset;
  }

 private:
  bool read_exactly(void* data, std::size_t bytes) {
    boost::system::error_code error;
    boost::asio::read(socket_, boost::asio::buffer(data, bytes), error);
    return !error;
  }

  boost::asio::ip::tcp::socket socket_;
};

inline std::uint64_t metric(const StreamHub& hub, const std::string& name) {
  const std::string text = hub.metrics_text();
  const auto at = text.find("\n" + name + " ");
  if (at == std::string::npos) return 0;
  return std::stoull(text.substr(at + name.size() + 2));
}

// A hub on two io threads and an acceptor on 127.0.0.1: each open() is a client whose server side
// is a started StreamSession over the fake ports.
class StreamSessionTest : public ::testing::Test {
 protected:
  StreamSessionTest() : StreamSessionTest(StreamOptions{}) {}
  explicit StreamSessionTest(const StreamOptions& options)
      : hub_(options),
        work_(boost::asio::make_work_guard(io_)),
        acceptor_(io_,
                  boost::asio::ip::tcp::endpoint(boost::asio::ip::make_address("127.0.0.1"), 0)) {
    hub_.set_executor(io_.get_executor(), 2);
    for (int i = 0; i < 2; ++i) threads_.emplace_back([this] { io_.run(); });
  }

  // The test's clients are gone by now: their sessions see the connection end and leave the hub,
  // and the io threads run out of work once the last of them is released.
  ~StreamSessionTest() override {
    using namespace std::chrono_literals;
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (metric(hub_, "mobot_stream_clients") > 0 &&
           std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(5ms);
    }
    EXPECT_EQ(metric(hub_, "mobot_stream_clients"), 0U) << "sessions outlived their clients";
    work_.reset();
    while (!io_.stopped() && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(5ms);
    }
    io_.stop();
    for (auto& thread : threads_) thread.join();
  }

  // A client whose server side is a started session that has said hello. `early` is what the
  // session got together with the upgrade request (the bytes behind it in the HTTP read).
  std::unique_ptr<Client> open(Role role = Role::kViewer, int receive_buffer = 0,
                               std::string early = "") {
    auto client = std::make_unique<Client>(client_io_, acceptor_.local_endpoint(), receive_buffer);
    boost::asio::ip::tcp::socket server_side(boost::asio::make_strand(io_));
    acceptor_.accept(server_side);
    // The fake's tokens: viewer is 1, operator 2, admin 3 (fake_ports.h); each client its own id.
    const Caller caller{static_cast<std::int64_t>(role) + 1, role, "test"};
    auto registration = hub_.clients().open("127.0.0.1:1", 0.0);
    // As the HTTP session does on the upgrade.
    registration->became_stream();
    registration->identify(caller);
    const ClientContext connection{registration->id(), "127.0.0.1:1"};
    std::make_shared<StreamSession>(std::move(server_side), hub_, robot_.ports(simulated_),
                                    StreamPeer{caller, connection, std::move(registration)},
                                    std::move(early))
        ->start();
    EXPECT_TRUE(client->read_until(R"("op":"hello")"));
    return client;
  }

  // Waits up to 5 s for the hub to have `clients` sessions.
  bool wait_for_clients(std::uint64_t clients) {
    using namespace std::chrono_literals;
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (metric(hub_, "mobot_stream_clients") != clients) {
      if (std::chrono::steady_clock::now() > deadline) return false;
      std::this_thread::sleep_for(5ms);
    }
    return true;
  }

  FakePorts robot_;
  bool simulated_ = true;  // whether the sessions opened next get the simulator's port
  std::uint64_t clients_opened_ = 0;
  StreamHub hub_;
  boost::asio::io_context io_;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work_;
  boost::asio::ip::tcp::acceptor acceptor_;
  std::vector<std::thread> threads_;
  boost::asio::io_context client_io_;
};

}  // namespace mobot::api::test
