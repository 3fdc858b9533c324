#include "api/stream_request.h"

#include "api/api_error.h"

#include <algorithm>
#include <array>

namespace mobot::api {
namespace {

std::vector<std::string> topic_names(const nlohmann::json& request, const char* op) {
  const auto topics = request.find("topics");
  if (topics == request.end() || !topics->is_array()) {
    throw ApiError(400, "invalid_topics", std::string(op) + " needs an array field 'topics'");
  }
  std::vector<std::string> names;
  for (const auto& name : *topics) {
    if (!name.is_string()) throw ApiError(400, "invalid_topics", "topic names are strings");
    names.push_back(name.get<std::string>());
  }
  return names;
}

SubscribeRequest parse_subscribe(const nlohmann::json& request) {
  SubscribeRequest subscribe;
  subscribe.topics = topic_names(request, "subscribe");
  if (const auto encoding = request.find("encoding"); encoding != request.end()) {
    if (*encoding != "json" && *encoding != "binary") {
      throw ApiError(400, "invalid_encoding", "encoding is \"json\" or \"binary\"");
    }
    subscribe.binary = *encoding == "binary";
  }
  if (request.contains("max_rate_hz")) {
    const double rate_hz = require_number(request, "max_rate_hz", 0.1, 1000.0);
    subscribe.min_interval_us = static_cast<std::int64_t>(1e6 / rate_hz);
  }
  subscribe.camera_quality = optional_integer(request, "camera_quality", 1, 100).value_or(0);
  subscribe.max_kbps = optional_number(request, "max_kbps", 0.0, 1e6);
  return subscribe;
}

// JavaScript's numbers count whole numbers exactly up to 2^53 - 1.
constexpr std::uint64_t kMaxSeq = (std::uint64_t{1} << 53) - 1;

std::optional<std::uint64_t> optional_seq(const nlohmann::json& request) {
  const auto field = request.find("seq");
  if (field == request.end()) return std::nullopt;
  if (field->is_number_unsigned() && field->get<std::uint64_t>() <= kMaxSeq) {
    return field->get<std::uint64_t>();
  }
  if (field->is_number_integer() && field->get<std::int64_t>() == 0) return 0;
  throw ApiError(400, "invalid_field", "'seq' must be a whole number from 0 to 2^53 - 1");
}

StreamTeleopRequest parse_stream_teleop(const nlohmann::json& request, Role role) {
  if (role < Role::kOperator) throw ApiError(403, "forbidden", "teleop needs the operator role");
  StreamTeleopRequest teleop;
  teleop.command = parse_teleop(request);
  teleop.seq = optional_seq(request);
  teleop.sent_ms = optional_number(request, "sent_ms", 0.0, 1e15);
  return teleop;
}

EstopRequest parse_stream_estop(const nlohmann::json& request, Role role) {
  if (role < Role::kOperator) throw ApiError(403, "forbidden", "estop needs the operator role");
  return EstopRequest{require_bool(request, "engaged")};
}

}  // namespace

StreamMessage read_stream_message(std::string_view text) {
  nlohmann::json request;
  try {
    request = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception&) {
    throw ApiError(400, "malformed_json", "the message is not valid JSON");
  }
  const auto op_field = request.is_object() ? request.find("op") : request.end();
  if (!request.is_object() || op_field == request.end() || !op_field->is_string()) {
    throw ApiError(400, "missing_op", "a message needs a string field 'op'");
  }
  std::string op = op_field->get<std::string>();
  return {std::move(request), std::move(op)};
}

StreamRequest parse_stream_request(const StreamMessage& message, Role role) {
  const nlohmann::json& request = message.body;
  const std::string& op = message.op;
  if (op == "subscribe") return parse_subscribe(request);
  if (op == "unsubscribe") return UnsubscribeRequest{topic_names(request, "unsubscribe")};
  if (op == "teleop") return parse_stream_teleop(request, role);
  if (op == "estop") return parse_stream_estop(request, role);
  if (op == "ping") {
    const auto id = request.find("id");
    return PingRequest{id == request.end() ? nlohmann::json(nullptr) : *id};
  }
  throw ApiError(400, "unknown_op", "unknown op '" + op + "'");
}

nlohmann::json request_identity(std::string_view op, std::optional<std::uint64_t> seq) {
  nlohmann::json identity = nlohmann::json::object();
  identity["request_op"] = op;
  if (seq) identity["seq"] = *seq;
  return identity;
}

nlohmann::json request_identity(const StreamMessage& message) {
  static constexpr std::array<std::string_view, 5> kOps{"subscribe", "unsubscribe", "teleop",
                                                        "estop", "ping"};
  if (std::find(kOps.begin(), kOps.end(), message.op) == kOps.end())
    return nlohmann::json::object();
  nlohmann::json identity = request_identity(message.op);
  if (message.op == "teleop") {
    if (const auto seq = message.body.find("seq"); seq != message.body.end() && seq->is_number()) {
      identity["seq"] = *seq;
    }
  }
  return identity;
}

StreamRequest parse_stream_request(std::string_view text, Role role) {
  return parse_stream_request(read_stream_message(text), role);
}

}  // namespace mobot::api
