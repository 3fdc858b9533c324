// The TLS front (api/tls_tunnel.cpp) on two io threads, an echo server behind it on the plain
// end: bytes both ways intact through many records, the client's address handed over, the client
// closed with a close_notify when the server side ends, and no byte at all for a client that is
// not speaking TLS. deploy/test.sh runs it under ThreadSanitizer with the other api unit tests.
#include "api/tls_tunnel.h"

#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/write.hpp>
#include <chrono>
#include <filesystem>
#include <mutex>
#include <random>
#include <thread>
#include <unistd.h>

#include "api/tls_context.h"
#include "support/test_certificate.h"

namespace mobot::api {
namespace {

using tcp = boost::asio::ip::tcp;
namespace ssl = boost::asio::ssl;
using namespace std::chrono_literals;

// Echoes what it reads on the tunnel's plain end; `close_after` bytes echoed, it closes its end.
class EchoSession : public std::enable_shared_from_this<EchoSession> {
 public:
  EchoSession(tcp::socket socket, std::size_t close_after)
      : socket_(std::move(socket)), close_after_(close_after) {}
  void start() { read(); }

 private:
  void read() {
    socket_.async_read_some(boost::asio::buffer(buffer_),
                            [self = shared_from_this()](boost::system::error_code error,
                                                        std::size_t bytes) {
                              if (error) {
                                self->close();
                                return;
                              }
                              self->echo(bytes);
                            });
  }
  void echo(std::size_t bytes) {
    boost::asio::async_write(socket_, boost::asio::buffer(buffer_.data(), bytes),
                             [self = shared_from_this(), bytes](boost::system::error_code error,
                                                                std::size_t) {
                               self->echoed_ += bytes;
                               if (error || self->echoed_ >= self->close_after_) {
                                 self->close();
                                 return;
                               }
                               self->read();
                             });
  }
  void close() {
    boost::system::error_code ignored;
    socket_.shutdown(tcp::socket::shutdown_both, ignored);
    socket_.close(ignored);
  }

  tcp::socket socket_;
  std::size_t close_after_;
  std::size_t echoed_ = 0;
  std::array<char, 4096> buffer_{};
};

class TlsTunnelTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("mobot_tls_tunnel_" + std::to_string(::getpid()));
    certificate_ = testing::make_test_certificate(dir_);
    server_context_.emplace(
        make_tls_server_context({certificate_.cert_file, certificate_.key_file}));
    acceptor_.open(tcp::v4());
    acceptor_.bind({boost::asio::ip::make_address("127.0.0.1"), 0});
    acceptor_.listen();
    accept();
    for (int i = 0; i < 2; ++i) threads_.emplace_back([this] { io_.run(); });
  }
  void TearDown() override {
    boost::asio::post(acceptor_.get_executor(), [this] { acceptor_.close(); });
    work_.reset();
    for (auto& thread : threads_) thread.join();
    std::filesystem::remove_all(dir_);
  }

  void accept() {
    acceptor_.async_accept(boost::asio::make_strand(io_), [this](boost::system::error_code error,
                                                                 tcp::socket socket) {
      if (error) return;
      TlsTunnelTimeouts timeouts;
      timeouts.handshake = 1s;
      std::make_shared<TlsTunnel>(
          std::move(socket), *server_context_, counters_, timeouts, boost::asio::make_strand(io_),
          [this](tcp::socket plain_end, std::string peer) {
            {
              std::lock_guard lock(mutex_);
              peers_.push_back(std::move(peer));
            }
            std::make_shared<EchoSession>(std::move(plain_end), close_after_)->start();
          })
          ->start();
      accept();
    });
  }

  // A blocking TLS client on the test thread that trusts the test certificate.
  struct Client {
    boost::asio::io_context io;
    ssl::context context{ssl::context::tls_client};
    std::unique_ptr<ssl::stream<tcp::socket>> stream;
  };
  std::unique_ptr<Client> connect_tls() {
    auto client = std::make_unique<Client>();
    client->context.load_verify_file(certificate_.cert_file.string());
    client->context.set_verify_mode(ssl::verify_peer);
    client->stream = std::make_unique<ssl::stream<tcp::socket>>(client->io, client->context);
    client->stream->next_layer().connect(acceptor_.local_endpoint());
    client->stream->handshake(ssl::stream_base::client);
    return client;
  }
  std::string local_address(const tcp::socket& socket) {
    const auto local = socket.local_endpoint();
    return local.address().to_string() + ":" + std::to_string(local.port());
  }

  std::filesystem::path dir_;
  testing::TestCertificate certificate_;
  std::optional<ssl::context> server_context_;
  boost::asio::io_context io_;
  std::optional<boost::asio::executor_work_guard<boost::asio::io_context::executor_type>> work_{
      io_.get_executor()};
  tcp::acceptor acceptor_{io_};
  std::vector<std::thread> threads_;
  TlsCounters counters_;
  std::size_t close_after_ = std::numeric_limits<std::size_t>::max();
  std::mutex mutex_;
  std::vector<std::string> peers_;
};

TEST_F(TlsTunnelTest, BytesGoBothWaysIntactThroughManyRecords) {
  auto client = connect_tls();
  std::string sent(1 << 20, '\0');
  std::mt19937 random(7);
  for (auto& c : sent) c = static_cast<char>(random());
  // A TLS stream is read and written from one thread: 64 KiB out, then its echo back, which the
  // socket buffers on the way hold while the test is writing.
  constexpr std::size_t kRound = 64 * 1024;
  std::string received;
  for (std::size_t at = 0; at < sent.size(); at += kRound) {
    boost::asio::write(*client->stream, boost::asio::buffer(sent.data() + at, kRound));
    std::string echo(kRound, '\0');
    boost::asio::read(*client->stream, boost::asio::buffer(echo));
    received += echo;
  }
  EXPECT_TRUE(received == sent) << "the echo differs from what was sent";
  EXPECT_EQ(counters_.handshakes.load(), 1U);
  EXPECT_EQ(counters_.handshake_failures.load(), 0U);
  std::lock_guard lock(mutex_);
  ASSERT_EQ(peers_.size(), 1U);
  EXPECT_EQ(peers_[0], local_address(client->stream->next_layer()));
}

TEST_F(TlsTunnelTest, TheServerSideClosingEndsTheClientWithACloseNotify) {
  close_after_ = 5;
  auto client = connect_tls();
  boost::asio::write(*client->stream, boost::asio::buffer(std::string("hello")));
  std::string echoed(5, '\0');
  boost::asio::read(*client->stream, boost::asio::buffer(echoed));
  EXPECT_EQ(echoed, "hello");
  char more = 0;
  boost::system::error_code error;
  client->stream->read_some(boost::asio::buffer(&more, 1), error);
  // asio reports a received close_notify as eof; a connection cut without one as stream_truncated.
  EXPECT_EQ(error, boost::asio::error::eof) << error.message();
}

TEST_F(TlsTunnelTest, ANonTlsClientGetsNoByteAndIsCounted) {
  boost::asio::io_context io;
  tcp::socket plain(io);
  plain.connect(acceptor_.local_endpoint());
  boost::asio::write(plain, boost::asio::buffer(std::string("GET / HTTP/1.1\r\nHost: x\r\n\r\n")));
  char byte = 0;
  boost::system::error_code error;
  const std::size_t got = plain.read_some(boost::asio::buffer(&byte, 1), error);
  EXPECT_EQ(got, 0U);
  EXPECT_TRUE(error == boost::asio::error::eof || error == boost::asio::error::connection_reset)
      << error.message();
  const auto deadline = std::chrono::steady_clock::now() + 2s;
  while (counters_.handshake_failures.load() == 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(5ms);
  }
  EXPECT_EQ(counters_.handshake_failures.load(), 1U);
  std::lock_guard lock(mutex_);
  EXPECT_TRUE(peers_.empty()) << "nothing may be handed to a session";
}

TEST_F(TlsTunnelTest, ASilentClientIsClosedAtTheHandshakeTimeout) {
  boost::asio::io_context io;
  tcp::socket silent(io);
  silent.connect(acceptor_.local_endpoint());
  const auto started = std::chrono::steady_clock::now();
  char byte = 0;
  boost::system::error_code error;
  silent.read_some(boost::asio::buffer(&byte, 1), error);
  const auto waited = std::chrono::steady_clock::now() - started;
  EXPECT_TRUE(error) << "the connection must end";
  EXPECT_GE(waited, 900ms);
  EXPECT_LT(waited, 5s);
  EXPECT_EQ(counters_.handshake_failures.load(), 1U);
}

}  // namespace
}  // namespace mobot::api
