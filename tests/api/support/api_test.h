#pragma once

// Shared pieces of the API test suites: one mobotd per test suite, clients with each role, waits
// on the robot clock, and small map images built in memory.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "support/mobotd_process.h"
#include "support/test_client.h"

namespace mobot::testing {

using json = nlohmann::json;
using namespace std::chrono_literals;

// Polls `predicate` every few milliseconds until it holds or the wall-clock timeout passes.
inline bool wait_until(const std::function<bool()>& predicate,
                       std::chrono::milliseconds timeout = 10s,
                       std::chrono::milliseconds period = 5ms) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    if (predicate()) return true;
    std::this_thread::sleep_for(period);
  }
  return predicate();
}

// GET /api/v1/robot as JSON (fails the test when it is not a 200).
inline json robot_state(const HttpClient& client) {
  const HttpReply reply = client.get("/api/v1/robot");
  EXPECT_EQ(reply.status, 200) << reply.body;
  return reply.status == 200 ? reply.json() : json::object();
}

inline double robot_time(const HttpClient& client) {
  return robot_state(client).value("t", std::nan(""));
}

inline json sim_truth(const HttpClient& client) {
  const HttpReply reply = client.get("/api/v1/sim/truth");
  EXPECT_EQ(reply.status, 200) << reply.body;
  return reply.status == 200 ? reply.json() : json::object();
}

// Waits until the robot clock has advanced by `seconds` (robot time, whatever the time scale).
inline bool wait_robot_time(const HttpClient& client, double seconds,
                            std::chrono::milliseconds wall_timeout = 30s) {
  const double start = robot_time(client);
  return wait_until([&] { return robot_time(client) >= start + seconds; }, wall_timeout);
}

// Keeps a teleop command alive (re-sent every few ms of wall time, ttl 300 ms of robot time) for
// `seconds` of robot time, or until `stop` says so. Returns the replies' last body.
inline json drive_for(const HttpClient& operator_client, double v, double w, double seconds,
                      const std::function<bool()>& stop = nullptr) {
  const double start = robot_time(operator_client);
  json last;
  const auto wall_deadline = std::chrono::steady_clock::now() + 60s;
  while (std::chrono::steady_clock::now() < wall_deadline) {
    const HttpReply reply =
        operator_client.post("/api/v1/teleop", json{{"v", v}, {"w", w}, {"ttl_ms", 300}});
    EXPECT_EQ(reply.status, 200) << reply.body;
    if (reply.status != 200) break;
    last = reply.json();
    if (stop && stop()) break;
    if (robot_time(operator_client) >= start + seconds) break;
    std::this_thread::sleep_for(2ms);
  }
  return last;
}

// Creates a token with `role` through the admin API and returns its plain value.
inline std::string create_token(const HttpClient& admin, const std::string& role,
                                const std::string& label = "api test") {
  const HttpReply reply = admin.post("/api/v1/tokens", json{{"role", role}, {"label", label}});
  EXPECT_EQ(reply.status, 201) << reply.body;
  if (reply.status != 201) return "no-token-created";
  return reply.json().at("token").get<std::string>();
}

// One mobotd per test suite (SetUpTestSuite), reached as admin (the --token), operator and
// viewer. `Tag` gives every suite its own server.
template <class Tag>
class ServerSuite : public ::testing::Test {
 public:
  static MobotdProcess::Options server_options() { return {}; }

  static void SetUpTestSuite() {
    server_ = std::make_unique<MobotdProcess>(Tag::server_options());
    const HttpClient admin(server_->port(), server_->token());
    operator_token_ = create_token(admin, "operator", "suite operator");
    viewer_token_ = create_token(admin, "viewer", "suite viewer");
  }
  static void TearDownTestSuite() { server_.reset(); }

 protected:
  void SetUp() override {
    ASSERT_TRUE(server_ != nullptr);
    ASSERT_TRUE(server_->alive()) << "mobotd is not running any more";
  }
  void TearDown() override {
    // Whatever a test did, the server must still be there for the next one.
    EXPECT_TRUE(server_->alive()) << "mobotd died during the test";
  }

  static MobotdProcess& server() { return *server_; }
  static std::uint16_t port() { return server_->port(); }
  static HttpClient admin() { return {server_->port(), server_->token()}; }
  static HttpClient operator_client() { return {server_->port(), operator_token_}; }
  static HttpClient viewer() { return {server_->port(), viewer_token_}; }
  static HttpClient anonymous() { return {server_->port(), ""}; }
  static const std::string& operator_token() { return operator_token_; }
  static const std::string& viewer_token() { return viewer_token_; }

  static inline std::unique_ptr<MobotdProcess> server_;
  static inline std::string operator_token_;
  static inline std::string viewer_token_;
};

// ----- map images -------------------------------------------------------------------------------

// A binary PGM (P5) of width x height grey pixels, row 0 at the top.
inline std::string make_pgm(int width, int height, const std::vector<std::uint8_t>& pixels) {
  std::string out = "P5\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n";
  out.append(reinterpret_cast<const char*>(pixels.data()), pixels.size());
  return out;
}

namespace detail {

inline std::uint32_t crc32(const std::string& bytes) {
  std::uint32_t crc = 0xFFFFFFFFU;
  for (const char c : bytes) {
    crc ^= static_cast<unsigned char>(c);
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320U & (0U - (crc & 1U)));
  }
  return crc ^ 0xFFFFFFFFU;
}

inline void put_be32(std::string& out, std::uint32_t value) {
  for (int shift = 24; shift >= 0; shift -= 8)
    out.push_back(static_cast<char>((value >> shift) & 0xFF));
}

inline void png_chunk(std::string& out, const std::string& type, const std::string& data) {
  put_be32(out, static_cast<std::uint32_t>(data.size()));
  const std::string body = type + data;
  out += body;
  put_be32(out, crc32(body));
}

}  // namespace detail

// An 8-bit greyscale PNG (no zlib needed: the image data is in stored deflate blocks).
inline std::string make_png(int width, int height, const std::vector<std::uint8_t>& pixels) {
  std::string raw;
  for (int row = 0; row < height; ++row) {
    raw.push_back('\0');  // filter: none
    raw.append(reinterpret_cast<const char*>(pixels.data()) + static_cast<std::size_t>(row) * width,
               static_cast<std::size_t>(width));
  }
  std::string zlib = {'\x78', '\x01'};
  std::size_t at = 0;
  do {
    const std::size_t n = std::min<std::size_t>(65535, raw.size() - at);
    const bool last = at + n == raw.size();
    zlib.push_back(last ? '\x01' : '\x00');
    zlib.push_back(static_cast<char>(n & 0xFF));
    zlib.push_back(static_cast<char>(n >> 8));
    zlib.push_back(static_cast<char>(~n & 0xFF));
    zlib.push_back(static_cast<char>((~n >> 8) & 0xFF));
    zlib.append(raw, at, n);
    at += n;
  } while (at < raw.size());
  std::uint32_t a = 1, b = 0;
  for (const char c : raw) {
    a = (a + static_cast<unsigned char>(c)) % 65521U;
    b = (b + a) % 65521U;
  }
  detail::put_be32(zlib, (b << 16) | a);

  std::string png = "\x89PNG\r\n\x1a\n";
  std::string header;
  detail::put_be32(header, static_cast<std::uint32_t>(width));
  detail::put_be32(header, static_cast<std::uint32_t>(height));
  header += std::string{'\x08', '\x00', '\x00', '\x00', '\x00'};  // 8-bit grey
  detail::png_chunk(png, "IHDR", header);
  detail::png_chunk(png, "IDAT", zlib);
  detail::png_chunk(png, "IEND", "");
  return png;
}

// A width x height test map: a black (occupied) border, a white (free) inside, and a grey
// (unknown) block in the top-left quarter of the inside.
inline std::vector<std::uint8_t> test_map_pixels(int width, int height) {
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width) * height, 254);
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width; ++col) {
      std::uint8_t& p = pixels[static_cast<std::size_t>(row) * width + col];
      if (row == 0 || col == 0 || row == height - 1 || col == width - 1) {
        p = 0;
      } else if (row < height / 2 && col < width / 2 && row > 1 && col > 1) {
        p = 205;
      }
    }
  }
  return pixels;
}

inline json map_import_body(const std::string& name, const std::string& image_bytes,
                            double resolution = 0.1) {
  return {{"name", name},
          {"resolution", resolution},
          {"origin", {{"x", -1.0}, {"y", -2.0}, {"theta", 0.0}}},
          {"image_base64", base64_encode(image_bytes)}};
}

// The last event of `kind` in the current (newest) run's events, or null.
inline json find_event(const HttpClient& client, std::int64_t run_id, const std::string& kind) {
  const HttpReply reply = client.get("/api/v1/runs/" + std::to_string(run_id) + "/events");
  EXPECT_EQ(reply.status, 200) << reply.body;
  if (reply.status != 200) return nullptr;
  json found = nullptr;
  for (const auto& event : reply.json()) {
    if (event.value("kind", "") == kind) found = event;
  }
  return found;
}

// The id of the run that is open (no "ended"): the current process's run.
inline std::int64_t current_run_id(const HttpClient& client) {
  const HttpReply reply = client.get("/api/v1/runs");
  EXPECT_EQ(reply.status, 200) << reply.body;
  if (reply.status != 200) return -1;
  std::int64_t id = -1;
  for (const auto& run : reply.json()) {
    if (!run.contains("ended")) id = std::max<std::int64_t>(id, run.at("id").get<std::int64_t>());
  }
  return id;
}

}  // namespace mobot::testing
