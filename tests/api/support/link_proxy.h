// A TCP proxy on loopback that makes the link to mobotd look like a long, lossy internet path
// (the kernel's netem is not available to the tests): bytes arrive `delay` late in each
// direction; a share of the chunks read is held back `hold` more, the way a lost segment is
// retransmitted, so everything behind it waits too (TCP delivers in order); cut() stops all
// traffic both ways without closing anything, as a pulled cable or a radio out of range does:
// neither end hears a thing, and what they send waits in the buffers until restore().
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>

namespace mobot::testing {

struct LinkImpairment {
  std::chrono::milliseconds delay{0};  // one way
  double hold_fraction = 0.0;          // of the chunks read, 0..1
  std::chrono::milliseconds hold{300};
  std::uint32_t seed = 1;
};

class LinkProxy {
 public:
  LinkProxy(std::uint16_t target_port, LinkImpairment impairment);
  ~LinkProxy();
  LinkProxy(const LinkProxy&) = delete;
  LinkProxy& operator=(const LinkProxy&) = delete;

  // Where the clients connect instead of mobotd.
  std::uint16_t port() const { return port_; }
  void cut();
  void restore();
  // Chunks held back so far (the 2 % of a lossy link), for the tests' report.
  std::uint64_t chunks_held() const { return chunks_held_.load(); }

 private:
  class Pipe;
  struct Connection;

  void accept_next();

  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  const std::uint16_t target_port_;
  const LinkImpairment impairment_;
  std::uint16_t port_ = 0;
  bool cut_ = false;  // on the io thread
  std::atomic<std::uint64_t> chunks_held_{0};
  std::vector<std::shared_ptr<Connection>> connections_;  // on the io thread
  std::uint32_t next_seed_;
  std::thread thread_;
};

}  // namespace mobot::testing
