// libFuzzer target: a stream client's JSON text messages as the session parses them
// (api/stream_request: parse_stream_request, with json_request's field checks), for a viewer and
// an operator. Beyond not crashing: the only exception is ApiError with a documented code, what
// is accepted is within the documented ranges (the session acts on it unchecked), and what an
// error reply would name of the message (request_identity) is a known op and a number.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <set>
#include <string>
#include <string_view>
#include <variant>

#include "api/api_error.h"
#include "api/stream_request.h"

namespace {

using namespace mobot::api;

void check(bool condition) {
  if (!condition) __builtin_trap();
}

// docs/api.md, "Client ops": the error codes a message is answered with.
bool is_documented(const ApiError& error) {
  static const std::set<std::string> kCodes{"malformed_json", "missing_op",       "unknown_op",
                                            "invalid_topics", "invalid_encoding", "invalid_field",
                                            "missing_field"};
  if (error.code() == "forbidden") return error.http_status() == 403;
  return error.http_status() == 400 && kCodes.contains(error.code());
}

void check_accepted(const StreamRequest& request, Role role) {
  if (const auto* subscribe = std::get_if<SubscribeRequest>(&request)) {
    // 0.1 .. 1000 Hz, or every frame.
    check(subscribe->min_interval_us == 0 ||
          (subscribe->min_interval_us >= 1000 && subscribe->min_interval_us <= 10'000'000));
    check(subscribe->camera_quality >= 0 && subscribe->camera_quality <= 100);
  } else if (const auto* stream_teleop = std::get_if<StreamTeleopRequest>(&request)) {
    const TeleopRequest* teleop = &stream_teleop->command;
    check(role >= Role::kOperator);
    check(std::isfinite(teleop->twist.linear_mps) && std::abs(teleop->twist.linear_mps) <= 100);
    check(std::isfinite(teleop->twist.angular_radps) &&
          std::abs(teleop->twist.angular_radps) <= 100);
    check(teleop->ttl_ms >= 50 && teleop->ttl_ms <= 1000);
    check(!stream_teleop->seq || *stream_teleop->seq < (std::uint64_t{1} << 53));
    check(!stream_teleop->sent_ms ||
          (std::isfinite(*stream_teleop->sent_ms) && *stream_teleop->sent_ms >= 0.0));
  } else if (std::holds_alternative<EstopRequest>(request)) {
    check(role >= Role::kOperator);
  } else if (const auto* ping = std::get_if<PingRequest>(&request)) {
    // The pong echoes the id; the session writes it with invalid UTF-8 replaced.
    ping->id.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  }
}

// What an error reply names of a message: an object with at most a known op and a number.
void check_identity(const nlohmann::json& identity) {
  check(identity.is_object() && identity.size() <= 2);
  if (const auto op = identity.find("request_op"); op != identity.end()) {
    static const std::set<std::string> kOps{"subscribe", "unsubscribe", "teleop", "estop", "ping"};
    check(op->is_string() && kOps.contains(op->get<std::string>()));
  }
  if (const auto seq = identity.find("seq"); seq != identity.end()) check(seq->is_number());
  identity.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  for (const Role role : {Role::kViewer, Role::kOperator}) {
    try {
      const StreamMessage message = read_stream_message(text);
      check_identity(request_identity(message));
      check_accepted(parse_stream_request(message, role), role);
    } catch (const ApiError& error) {
      check(is_documented(error));
    }
  }
  return 0;
}
