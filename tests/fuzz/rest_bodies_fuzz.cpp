// libFuzzer target: REST requests (method, target, token, body) through the router
// (api/rest_api.*) against the unit tests' fake robot (tests/unit/api/fake_ports.h), a few per
// input so that one request can meet the state another left (the operator lock, a zone). Beyond
// not crashing, each request is answered exactly once and before handle() returns (the fakes
// complete at once), never with a 5xx, and a refused one (4xx) changes nothing: the state changes
// the fakes accepted, the tokens made and the operator lock's holder are as they were. A static
// file is only ever one of the dashboard's.
//
// The input format is rest_fuzz_input.h's, which the API test that replays the corpus against a
// real mobotd reads too.
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
#include "rest_fuzz_input.h"

namespace {

using namespace mobot::api;
namespace fuzz = mobot::fuzz;

void check(bool condition) {
  if (!condition) __builtin_trap();
}

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

Request make_request(const fuzz::RestFuzzRecord& record) {
  Request request{http::string_to_verb(record.method()), record.target, 11};
  if (const auto& credential = record.credential(); !credential.empty()) {
    request.set(http::field::authorization,
                std::string(credential.scheme) + std::string(credential.name));
  }
  request.set(http::field::content_type, "application/json");
  request.body() = record.body;
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

void run_one(RestApi& rest, test::FakePorts& robot, StreamHub& hub,
             const fuzz::RestFuzzRecord& record) {
  if (!record.target_reaches_router()) return;
  const Request request = make_request(record);
  // What a request may see of the fakes: all refusing, or all accepting.
  if (record.fakes_refuse()) {
    robot.answers.refusal = DomainError{ErrorKind::kConflict, "refused", "the fake refuses"};
  } else {
    robot.answers.refusal.reset();
  }
  const Snapshot before = snapshot(robot, hub);
  std::optional<Response> reply;
  int replies = 0;
  const ClientContext client{record.connection(), "127.0.0.1:4000"};
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
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  for (const fuzz::RestFuzzRecord& record : fuzz::rest_fuzz_records(input)) {
    run_one(rest, robot, hub, record);
  }
  return 0;
}
