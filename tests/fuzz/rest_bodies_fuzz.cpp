// libFuzzer target: REST requests (method, target, token, body) through the router
// (api/rest_api.*) against the unit tests' fake robot (tests/unit/api/fake_ports.h), a few per
// input so that one request can meet the state another left (the operator lock, a zone). Beyond
// not crashing, each request is answered exactly once and before handle() returns (the fakes
// complete at once), never with a 5xx, and a refused one (4xx) changes nothing: the state changes
// the fakes accepted, the tokens made and the operator lock's holder are as they were. A static
// file is only ever one of the dashboard's.
//
// An input is records separated by NUL bytes, each: a flags byte (method, token, the fakes
// refusing everything, which connection), the target, '\n', the body.
#include <unistd.h>
#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "api/rest_api.h"
#include "api/stream_hub.h"
#include "fake_ports.h"

namespace {

using namespace mobot::api;

void check(bool condition) {
  if (!condition) __builtin_trap();
}

constexpr std::array<http::verb, 8> kMethods{
    http::verb::get,   http::verb::post, http::verb::put,     http::verb::delete_,
    http::verb::patch, http::verb::head, http::verb::options, http::verb::post};
constexpr std::array<std::string_view, 8> kAuthorization{"",
                                                         "Bearer viewer",
                                                         "Bearer operator",
                                                         "Bearer admin",
                                                         "bearer operator2",
                                                         "Bearer nobody",
                                                         "Bearer",
                                                         "Basic b3BlcmF0b3I="};
constexpr std::size_t kMaxRecords = 4;

// The dashboard: two files in a directory of their own.
struct WebDir {
  std::filesystem::path dir;
  std::string index = "<!doctype html><title>mobot</title>";
  std::string asset = "console.log('mobot');";

  WebDir()
      : dir(std::filesystem::temp_directory_path() /
            ("mobot_fuzz_web_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(dir / "assets");
    std::ofstream(dir / "index.html", std::ios::binary) << index;
    std::ofstream(dir / "assets" / "app.js", std::ios::binary) << asset;
  }
  ~WebDir() {
    std::error_code ignored;
    std::filesystem::remove_all(dir, ignored);
  }
};

const WebDir& web_dir() {
  static const WebDir dir;
  return dir;
}

struct Snapshot {
  std::vector<std::string> accepted;
  int tokens_created = 0;
  std::optional<std::pair<std::int64_t, std::uint64_t>> lock_holder;  // token id, connection
};

Snapshot snapshot(test::FakePorts& robot, StreamHub& hub) {
  Snapshot state{robot.answers.accepted(), robot.tokens.created, std::nullopt};
  if (const auto holder = hub.operator_lock().holder(std::chrono::steady_clock::now())) {
    state.lock_holder = {holder->claimant.caller.token_id, holder->claimant.client_id};
  }
  return state;
}

Request make_request(std::uint8_t flags, std::string_view record) {
  const std::size_t line_end = record.find('\n');
  const std::string_view target = record.substr(0, line_end);
  const std::string_view body =
      line_end == std::string_view::npos ? std::string_view{} : record.substr(line_end + 1);
  Request request{kMethods[flags & 0x7U], target, 11};
  if (const auto authorization = kAuthorization[(flags >> 3) & 0x7U]; !authorization.empty()) {
    request.set(http::field::authorization, authorization);
  }
  request.set(http::field::content_type, "application/json");
  request.body() = body;
  request.prepare_payload();
  return request;
}

// A 200 from outside the API is one of the dashboard's files.
void check_static(const Request& request, const Response& response) {
  const std::string_view path = target_path(request.target());
  if (response.result_int() != 200 || path.starts_with("/api/") || path == "/metrics") return;
  const std::string& body = response.body();
  check(request.method() == http::verb::head || body == web_dir().index || body == web_dir().asset);
}

void run_one(RestApi& rest, test::FakePorts& robot, StreamHub& hub, std::uint8_t flags,
             std::string_view record) {
  // Beast's parser only hands on targets of visible characters (RFC 9112 3.2).
  const std::string_view target = record.substr(0, record.find('\n'));
  for (const char c : target) {
    if (static_cast<unsigned char>(c) <= 0x20 || c == 0x7F) return;
  }
  const Request request = make_request(flags, record);
  // What a request may see of the fakes: all refusing, or all accepting.
  if ((flags & 0x40U) != 0) {
    robot.answers.refusal = DomainError{ErrorKind::kConflict, "refused", "the fake refuses"};
  } else {
    robot.answers.refusal.reset();
  }
  const Snapshot before = snapshot(robot, hub);
  std::optional<Response> reply;
  int replies = 0;
  const ClientContext client{(flags & 0x80U) != 0 ? 2U : 1U, "127.0.0.1:4000"};
  rest.handle(
      request,
      [&](Response response) {
        ++replies;
        reply = std::move(response);
      },
      client);
  check(replies == 1);
  const unsigned status = reply->result_int();
  check(status < 500);
  if (status >= 400) {
    const Snapshot after = snapshot(robot, hub);
    check(after.accepted == before.accepted && after.tokens_created == before.tokens_created);
    // Refused before the robot (bad input, no right, a busy lock) or by it, the operator lock
    // is as it was.
    check(after.lock_holder == before.lock_holder);
  }
  check_static(request, *reply);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  test::FakePorts robot;
  StreamHub hub(StreamOptions{});
  RestApi rest(robot.ports(true), hub, {web_dir().dir, "fuzz"});
  std::string_view input(reinterpret_cast<const char*>(data), size);
  for (std::size_t record = 0; record < kMaxRecords && !input.empty(); ++record) {
    const std::size_t end = input.find('\0');
    const std::string_view bytes = input.substr(0, end);
    if (!bytes.empty()) {
      run_one(rest, robot, hub, static_cast<std::uint8_t>(bytes[0]), bytes.substr(1));
    }
    if (end == std::string_view::npos) break;
    input.remove_prefix(end + 1);
  }
  return 0;
}
