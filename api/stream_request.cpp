#include "api/stream_request.h"

#include "api/api_error.h"

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
  return subscribe;
}

TeleopRequest parse_stream_teleop(const nlohmann::json& request, Role role) {
  if (role < Role::kOperator) throw ApiError(403, "forbidden", "teleop needs the operator role");
  return parse_teleop(request);
}

}  // namespace

StreamRequest parse_stream_request(std::string_view text, Role role) {
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
  const auto& op = op_field->get_ref<const std::string&>();
  if (op == "subscribe") return parse_subscribe(request);
  if (op == "unsubscribe") return UnsubscribeRequest{topic_names(request, "unsubscribe")};
  if (op == "teleop") return parse_stream_teleop(request, role);
  if (op == "ping") {
    const auto id = request.find("id");
    return PingRequest{id == request.end() ? nlohmann::json(nullptr) : *id};
  }
  throw ApiError(400, "unknown_op", "unknown op '" + op + "'");
}

}  // namespace mobot::api
