#include "support/link_proxy.h"

#include <boost/asio/connect.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>
#include <array>
#include <deque>
#include <random>
#include <string>

namespace mobot::testing {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;
using Clock = std::chrono::steady_clock;

// One direction of one connection: reads from `from`, delivers to `to` when each chunk is due.
class LinkProxy::Pipe : public std::enable_shared_from_this<Pipe> {
 public:
  Pipe(tcp::socket& from, tcp::socket& to, const LinkImpairment& impairment, std::uint32_t seed,
       const bool& cut, std::atomic<std::uint64_t>& held)
      : from_(from), to_(to), impairment_(impairment), random_(seed), cut_(cut), held_(held),
        timer_(from.get_executor()) {}

  void start() { read(); }

  // The link is back: what waited goes, and reading starts again.
  void resume() {
    if (!reading_ && !ended_) read();
    deliver();
  }

  void close() {
    ended_ = true;
    boost::system::error_code ignored;
    timer_.cancel();
    from_.close(ignored);
    to_.close(ignored);
  }

 private:
  struct Chunk {
    Clock::time_point due;
    std::string bytes;
  };

  // Bytes waiting in the proxy at most; beyond, reading pauses (the sender's buffers fill).
  static constexpr std::size_t kMaxQueuedBytes = 4 << 20;

  void read() {
    if (cut_ || queued_bytes_ > kMaxQueuedBytes) return;
    reading_ = true;
    from_.async_read_some(asio::buffer(buffer_),
                          [self = shared_from_this()](boost::system::error_code error,
                                                      std::size_t bytes) {
                            self->on_read(error, bytes);
                          });
  }

  void on_read(boost::system::error_code error, std::size_t bytes) {
    reading_ = false;
    if (ended_) return;
    if (error) {
      // The sender closed: the other side learns it once what was sent before has arrived.
      source_closed_ = true;
      deliver();
      return;
    }
    Clock::time_point due = Clock::now() + impairment_.delay;
    if (std::uniform_real_distribution<double>(0.0, 1.0)(random_) < impairment_.hold_fraction) {
      due += impairment_.hold;
      held_.fetch_add(1);
    }
    // In order, as TCP delivers: nothing overtakes a held chunk.
    if (!queue_.empty()) due = std::max(due, queue_.back().due);
    queue_.push_back({due, std::string(buffer_.data(), bytes)});
    queued_bytes_ += bytes;
    deliver();
    read();
  }

  void deliver() {
    if (writing_ || ended_ || cut_) return;
    if (queue_.empty()) {
      if (source_closed_) {
        boost::system::error_code ignored;
        to_.shutdown(tcp::socket::shutdown_send, ignored);
      }
      return;
    }
    if (queue_.front().due > Clock::now()) {
      if (timer_armed_) return;
      timer_armed_ = true;
      timer_.expires_at(queue_.front().due);
      timer_.async_wait([self = shared_from_this()](boost::system::error_code error) {
        self->timer_armed_ = false;
        if (!error) self->deliver();
      });
      return;
    }
    writing_ = true;
    asio::async_write(to_, asio::buffer(queue_.front().bytes),
                      [self = shared_from_this()](boost::system::error_code error, std::size_t) {
                        self->on_written(error);
                      });
  }

  void on_written(boost::system::error_code error) {
    writing_ = false;
    if (ended_) return;
    if (error) {
      close();
      return;
    }
    queued_bytes_ -= queue_.front().bytes.size();
    queue_.pop_front();
    deliver();
    if (!reading_ && !source_closed_) read();
  }

  tcp::socket& from_;
  tcp::socket& to_;
  const LinkImpairment& impairment_;
  std::mt19937 random_;
  const bool& cut_;
  std::atomic<std::uint64_t>& held_;
  asio::steady_timer timer_;
  std::array<char, 16384> buffer_{};
  std::deque<Chunk> queue_;
  std::size_t queued_bytes_ = 0;
  bool reading_ = false;
  bool writing_ = false;
  bool timer_armed_ = false;
  bool source_closed_ = false;
  bool ended_ = false;
};

struct LinkProxy::Connection {
  Connection(tcp::socket client_in, tcp::socket server_in)
      : client(std::move(client_in)), server(std::move(server_in)) {}
  tcp::socket client;
  tcp::socket server;
  std::shared_ptr<Pipe> upstream;    // client -> server
  std::shared_ptr<Pipe> downstream;  // server -> client
};

LinkProxy::LinkProxy(std::uint16_t target_port, LinkImpairment impairment)
    : acceptor_(io_, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0)),
      target_port_(target_port),
      impairment_(impairment),
      port_(acceptor_.local_endpoint().port()),
      next_seed_(impairment.seed) {
  accept_next();
  thread_ = std::thread([this] { io_.run(); });
}

LinkProxy::~LinkProxy() {
  asio::post(io_, [this] {
    boost::system::error_code ignored;
    acceptor_.close(ignored);
    for (auto& connection : connections_) {
      connection->upstream->close();
      connection->downstream->close();
    }
  });
  // The pipes' last handlers run with the sockets closed; then the io_context runs out of work.
  thread_.join();
}

void LinkProxy::cut() {
  asio::post(io_, [this] { cut_ = true; });
}

void LinkProxy::restore() {
  asio::post(io_, [this] {
    cut_ = false;
    for (auto& connection : connections_) {
      connection->upstream->resume();
      connection->downstream->resume();
    }
  });
}

void LinkProxy::accept_next() {
  acceptor_.async_accept([this](boost::system::error_code error, tcp::socket client) {
    if (error) return;
    tcp::socket server(io_);
    boost::system::error_code connect_error;
    server.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), target_port_),
                   connect_error);
    if (!connect_error) {
      server.set_option(tcp::no_delay(true), connect_error);
      client.set_option(tcp::no_delay(true), connect_error);
      auto connection = std::make_shared<Connection>(std::move(client), std::move(server));
      connection->upstream = std::make_shared<Pipe>(connection->client, connection->server,
                                                    impairment_, next_seed_++, cut_, chunks_held_);
      connection->downstream = std::make_shared<Pipe>(
          connection->server, connection->client, impairment_, next_seed_++, cut_, chunks_held_);
      connections_.push_back(connection);
      connection->upstream->start();
      connection->downstream->start();
    }
    accept_next();
  });
}

}  // namespace mobot::testing
