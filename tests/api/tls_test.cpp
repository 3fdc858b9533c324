// TLS on mobotd's own port (--tls-cert, --tls-key; docs/api.md "TLS"): https and wss with a
// certificate the test makes, Strict-Transport-Security on every answer, and nothing at all for a
// client that does not speak TLS: plain http, garbage, or a handshake that never comes (closed
// after the handshake timeout, without holding up anybody else). The clients' real addresses in
// GET /api/v1/clients, the handshake failures in /metrics, the start refused with a message for
// TLS files that are missing, unreadable or do not belong together, and no token in any log line.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <fstream>

#include "support/api_test.h"
#include "support/command.h"
#include "support/test_certificate.h"

namespace mobot::testing {
namespace {

// The value of an unlabelled sample in the Prometheus text, or -1.
double metric_value(const std::string& text, const std::string& name) {
  std::size_t at = 0;
  while ((at = text.find(name + " ", at)) != std::string::npos) {
    if (at == 0 || text[at - 1] == '\n') return std::stod(text.substr(at + name.size() + 1));
    at += name.size();
  }
  return -1.0;
}

std::uint16_t local_port(int fd) {
  sockaddr_in address{};
  socklen_t length = sizeof address;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
  return ntohs(address.sin_port);
}

class TlsTest : public ::testing::Test {
 public:
  static void SetUpTestSuite() {
    dir_ = MobotdProcess::make_temp_dir();
    certificate_ = make_test_certificate(dir_);
    MobotdProcess::Options options;
    options.tls_cert = certificate_.cert_file;
    options.tls_key = certificate_.key_file;
    server_ = std::make_unique<MobotdProcess>(options);
  }
  static void TearDownTestSuite() {
    server_.reset();
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }

 protected:
  void SetUp() override { ASSERT_TRUE(server_->alive()); }
  void TearDown() override { EXPECT_TRUE(server_->alive()) << "mobotd died during the test"; }

  static HttpClient admin() {
    return HttpClient(server_->port(), server_->token()).over_tls(certificate_.cert_file);
  }
  static double handshake_failures() {
    return metric_value(admin().get("/metrics").body, "mobot_tls_handshake_failures_total");
  }

  static inline std::filesystem::path dir_;
  static inline TestCertificate certificate_;
  static inline std::unique_ptr<MobotdProcess> server_;
};

TEST_F(TlsTest, TheReadyLineSaysHttpsAndTheApiAnswersOverTlsWithHsts) {
  EXPECT_TRUE(server_->secure());
  EXPECT_EQ(server_->base_url().rfind("https://127.0.0.1:", 0), 0U);
  const HttpReply robot = admin().get("/api/v1/robot");
  ASSERT_EQ(robot.status, 200) << robot.body;
  EXPECT_TRUE(robot.json().contains("pose"));
  EXPECT_EQ(robot.header("strict-transport-security"), "max-age=31536000");
  // Errors and the unauthenticated health check carry it too.
  const HttpReply refused = admin().with_token("").get("/api/v1/robot");
  EXPECT_EQ(refused.status, 401);
  EXPECT_EQ(refused.header("strict-transport-security"), "max-age=31536000");
  EXPECT_EQ(admin().get("/api/v1/health").header("strict-transport-security"), "max-age=31536000");
  // Several requests on one TLS connection (keep-alive) go through the tunnel in turn.
  RawConnection connection(server_->port());
  ASSERT_TRUE(connection.start_tls(certificate_.cert_file));
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(connection.send("GET /api/v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"));
    const auto reply = connection.read_http_reply(5s);
    ASSERT_TRUE(reply.has_value()) << "request " << i;
    EXPECT_EQ(reply->status, 200);
  }
}

// Bodies of many TLS records each way: a map image of a megabyte in, its PGM and the OpenAPI
// document out, byte for byte.
TEST_F(TlsTest, LargeBodiesGoThroughTheTunnelBothWaysIntact) {
  constexpr int kSide = 1000;
  const HttpReply imported = admin().post(
      "/api/v1/maps",
      map_import_body("tls big map", make_pgm(kSide, kSide, test_map_pixels(kSide, kSide))));
  ASSERT_EQ(imported.status, 201) << imported.body.substr(0, 300);
  const HttpReply pgm =
      admin().get("/api/v1/maps/" + std::to_string(imported.json().at("id").get<int>()) +
                  "/map.pgm");
  ASSERT_EQ(pgm.status, 200);
  EXPECT_EQ(pgm.body.rfind("P5\n1000 1000\n255\n", 0), 0U) << pgm.body.substr(0, 40);
  EXPECT_EQ(pgm.body.size(), std::string("P5\n1000 1000\n255\n").size() + kSide * kSide);
  std::ifstream file(MOBOT_OPENAPI_FILE, std::ios::binary);
  const std::string document{std::istreambuf_iterator<char>(file),
                             std::istreambuf_iterator<char>()};
  const HttpReply served = admin().get("/api/v1/openapi.json");
  ASSERT_EQ(served.status, 200);
  EXPECT_EQ(served.body, document);
}

// A wss client that stops reading holds back only itself: the others are served, the server's
// memory is bounded by the tunnel's chunk and the socket buffers, and the client, reading again,
// gets the newest frames.
TEST_F(TlsTest, AWssClientThatStopsReadingHoldsUpNobody) {
  WsClient slow(server_->port(), server_->token(), 4096, "", certificate_.cert_file);
  slow.send(json{{"op", "subscribe"}, {"topics", {"pose", "scan", "odom", "status"}}});
  ASSERT_TRUE(slow.read_until("pose").has_value());
  const auto until = std::chrono::steady_clock::now() + 3s;
  while (std::chrono::steady_clock::now() < until) {
    const auto started = std::chrono::steady_clock::now();
    EXPECT_EQ(admin().get("/api/v1/robot").status, 200);
    EXPECT_LT(std::chrono::steady_clock::now() - started, 2s);
    std::this_thread::sleep_for(200ms);
  }
  int poses = 0;
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (poses < 3 && std::chrono::steady_clock::now() < deadline) {
    if (slow.read_until("pose", 5s)) ++poses;
  }
  EXPECT_EQ(poses, 3);
  EXPECT_TRUE(slow.is_open());
}

TEST_F(TlsTest, AClientThatDoesNotTrustTheCertificateGetsNoAnswer) {
  const auto other = make_test_certificate(dir_, "other");
  const HttpReply reply = admin().over_tls(other.cert_file).get("/api/v1/health");
  EXPECT_EQ(reply.status, 0) << "a client that cannot verify the server must not get a reply";
}

TEST_F(TlsTest, AWssStreamSubscribesAndReceivesPoseFrames) {
  WsClient stream(server_->port(), server_->token(), 0, "", certificate_.cert_file);
  EXPECT_EQ(stream.hello().at("op"), "hello");
  stream.send(json{{"op", "subscribe"}, {"topics", {"pose"}}});
  int poses = 0;
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (poses < 5 && std::chrono::steady_clock::now() < deadline) {
    if (const auto pose = stream.read_until("pose", 5s)) {
      EXPECT_TRUE(pose->contains("data")) << pose->dump();
      ++poses;
    }
  }
  EXPECT_EQ(poses, 5);
  // Frames the client sends after the upgrade go through the tunnel too.
  stream.send(json{{"op", "ping"}, {"id", 7}});
  EXPECT_TRUE(stream.read_until("pong", 5s).has_value());
}

TEST_F(TlsTest, TheClientsListShowsTheRealAddressOfATlsClient) {
  WsClient stream(server_->port(), server_->token(), 0, "", certificate_.cert_file);
  const std::string address = "127.0.0.1:" + std::to_string(local_port(stream.fd()));
  bool found = false;
  ASSERT_TRUE(wait_until(
      [&] {
        for (const json& client : admin().get("/api/v1/clients").json()) {
          found = found || (client.at("kind") == "stream" && client.at("address") == address);
        }
        return found;
      },
      3s))
      << "no stream client at " << address << " in " << admin().get("/api/v1/clients").body;
}

TEST_F(TlsTest, PlainHttpToTheTlsPortGetsNoByteAndIsClosed) {
  const double failures_before = handshake_failures();
  RawConnection plain(server_->port());
  ASSERT_TRUE(plain.connected());
  ASSERT_TRUE(plain.send("GET /api/v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"));
  const std::string received = plain.read_for(3s);
  EXPECT_TRUE(received.empty()) << "plain http got " << received.size() << " bytes";
  EXPECT_TRUE(plain.eof()) << "the connection must be closed";
  EXPECT_TRUE(wait_until([&] { return handshake_failures() >= failures_before + 1; }, 2s))
      << "mobot_tls_handshake_failures_total did not count it";
  // A plain WebSocket upgrade is no different.
  EXPECT_EQ(ws_upgrade_status(server_->port(), "/api/v1/stream?token=" + server_->token()), 0);
}

TEST_F(TlsTest, GarbageInsteadOfAClientHelloIsClosed) {
  for (const std::string& garbage :
       {std::string("\x01\x02\x03 this is not TLS at all\r\n\r\n"),
        // A handshake record's first byte with nonsense after it: OpenSSL judges it.
        std::string("\x16\x03\x01\x00\x05hello, not a ClientHello", 29)}) {
    RawConnection connection(server_->port());
    ASSERT_TRUE(connection.send(garbage));
    EXPECT_TRUE(connection.closed_by_peer(5s));
  }
  EXPECT_EQ(admin().get("/api/v1/health").status, 200) << "the server goes on serving";
}

TEST_F(TlsTest, AStalledHandshakeIsClosedAfterTheTimeoutAndHoldsUpNobody) {
  RawConnection stalled(server_->port());  // connects, and never sends a byte
  ASSERT_TRUE(stalled.connected());
  const auto started = std::chrono::steady_clock::now();
  // Meanwhile another client is served at once.
  const auto served_started = std::chrono::steady_clock::now();
  EXPECT_EQ(admin().get("/api/v1/robot").status, 200);
  EXPECT_LT(std::chrono::steady_clock::now() - served_started, 3s);
  EXPECT_TRUE(stalled.closed_by_peer(20s)) << "a stalled handshake must be closed";
  const auto waited = std::chrono::steady_clock::now() - started;
  EXPECT_GE(waited, 8s) << "closed before the 10 s handshake timeout";
  EXPECT_LE(waited, 15s);
}

TEST_F(TlsTest, MetricsCountTheHandshakes) {
  const std::string metrics = admin().get("/metrics").body;
  EXPECT_GT(metric_value(metrics, "mobot_tls_handshakes_total"), 0.0) << metrics;
  EXPECT_GE(metric_value(metrics, "mobot_tls_handshake_failures_total"), 0.0) << metrics;
}

// ----- the start refused ------------------------------------------------------------------------

class TlsConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = MobotdProcess::make_temp_dir();
    certificate_ = make_test_certificate(dir_);
  }
  void TearDown() override {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }

  // mobotd with these extra arguments on a port of its own; it must exit, not serve.
  CommandResult start(std::vector<std::string> extra) const {
    std::vector<std::string> args{"--backend", "sim",  "--port", "0", "--bind", "127.0.0.1",
                                  "--data-dir", (dir_ / "data").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    return run_mobotd(args, 30s);
  }

  std::filesystem::path dir_;
  TestCertificate certificate_;
};

TEST_F(TlsConfigTest, OnlyACertificateIsRefusedNamingTheMissingKey) {
  const CommandResult result = start({"--tls-cert", certificate_.cert_file.string()});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.err.find("server.tls.key"), std::string::npos) << result.err;
  EXPECT_EQ(result.out.find("listening"), std::string::npos) << result.out;
  const CommandResult key_only = start({"--tls-key", certificate_.key_file.string()});
  EXPECT_NE(key_only.exit_code, 0);
  EXPECT_NE(key_only.err.find("server.tls.cert"), std::string::npos) << key_only.err;
}

TEST_F(TlsConfigTest, AMissingFileIsRefusedNamingIt) {
  const std::string missing = (dir_ / "no-such.crt").string();
  const CommandResult result =
      start({"--tls-cert", missing, "--tls-key", certificate_.key_file.string()});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.err.find(missing), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("server.tls.cert"), std::string::npos) << result.err;
}

TEST_F(TlsConfigTest, AFileThatIsNotPemIsRefusedNamingIt) {
  const auto not_pem = dir_ / "not-pem.key";
  std::ofstream(not_pem) << "this is no key\n";
  const CommandResult result = start(
      {"--tls-cert", certificate_.cert_file.string(), "--tls-key", not_pem.string()});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.err.find(not_pem.string()), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("private key"), std::string::npos) << result.err;
}

TEST_F(TlsConfigTest, AKeyThatIsNotTheCertificatesIsRefused) {
  const auto other = make_test_certificate(dir_, "other");
  const CommandResult result = start(
      {"--tls-cert", certificate_.cert_file.string(), "--tls-key", other.key_file.string()});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.err.find("does not match"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find(other.key_file.string()), std::string::npos) << result.err;
}

TEST_F(TlsConfigTest, TheConfigFileNamesTheFilesToo) {
  const auto config = dir_ / "tls.yaml";
  std::ofstream(config) << "server:\n  tls:\n    cert: " << certificate_.cert_file.string()
                        << "\n    key: " << certificate_.key_file.string() << "\n";
  MobotdProcess::Options options;
  options.extra_args = {"--config", config.string()};
  MobotdProcess server(options);
  EXPECT_TRUE(server.secure());
  EXPECT_EQ(HttpClient(server.port(), server.token())
                .over_tls(certificate_.cert_file)
                .get("/api/v1/health")
                .status,
            200);
  std::ofstream(config, std::ios::trunc)
      << "server:\n  tls:\n    cert: " << certificate_.cert_file.string() << "\n";
  const CommandResult result = start({"--config", config.string()});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.err.find("server.tls.key"), std::string::npos) << result.err;
}

// ----- no token in the log ----------------------------------------------------------------------

TEST(TlsLogTest, NoTokenAppearsInAnyLogLineEvenAtTrace) {
  const auto dir = MobotdProcess::make_temp_dir();
  const TestCertificate certificate = make_test_certificate(dir);
  const auto log = dir / "mobotd.log";
  std::vector<std::string> secrets;
  {
    MobotdProcess::Options options;
    options.tls_cert = certificate.cert_file;
    options.tls_key = certificate.key_file;
    options.log_level = "trace";
    options.stderr_file = log;
    options.token = "process-admin-token-0123456789";
    MobotdProcess server(options);
    const HttpClient admin =
        HttpClient(server.port(), server.token()).over_tls(certificate.cert_file);
    secrets.push_back(server.token());
    const std::string viewer = create_token(admin, "viewer", "log test");
    secrets.push_back(viewer);
    // In the header, good and bad.
    EXPECT_EQ(admin.with_token(viewer).get("/api/v1/robot").status, 200);
    EXPECT_EQ(admin.with_token("wrong-token-abcdef").get("/api/v1/robot").status, 401);
    secrets.push_back("wrong-token-abcdef");
    // In the query: the stream's, and one on a REST path where it means nothing.
    {
      WsClient stream(server.port(), viewer, 0, "", certificate.cert_file);
      stream.send(json{{"op", "subscribe"}, {"topics", {"pose"}}});
      EXPECT_TRUE(stream.read_until("pose").has_value());
    }
    EXPECT_EQ(admin.get("/api/v1/robot?token=" + viewer).status, 200);
    EXPECT_THROW(WsClient(server.port(), "query-token-unknown-42", 0, "", certificate.cert_file),
                 WsHandshakeError);
    secrets.push_back("query-token-unknown-42");
    // A plain-http client, whose failed handshake is logged.
    RawConnection plain(server.port());
    plain.send("GET /api/v1/stream?token=" + viewer + " HTTP/1.1\r\n\r\n");
    EXPECT_TRUE(plain.closed_by_peer(5s));
    EXPECT_EQ(server.terminate(), 0);
  }
  std::ifstream in(log);
  std::string line;
  int lines = 0;
  bool redacted_seen = false;
  while (std::getline(in, line)) {
    ++lines;
    redacted_seen = redacted_seen || line.find("token=REDACTED") != std::string::npos;
    for (const std::string& secret : secrets) {
      EXPECT_EQ(line.find(secret), std::string::npos) << "a token in the log: " << line;
    }
  }
  EXPECT_GT(lines, 3) << "the log at trace level is almost empty: is stderr captured?";
  EXPECT_TRUE(redacted_seen) << "the stream's request line should be logged, its token redacted";
  std::error_code ignored;
  std::filesystem::remove_all(dir, ignored);
}

}  // namespace
}  // namespace mobot::testing
