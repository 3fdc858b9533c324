#include "api/json_request.h"

#include <cmath>
#include <cstdint>
#include <numbers>

#include "api/api_error.h"

namespace mobot::api {
namespace {

[[noreturn]] void invalid(const char* key, const std::string& expectation) {
  throw ApiError(400, "invalid_field", std::string("'") + key + "' " + expectation);
}

const nlohmann::json& field(const nlohmann::json& object, const char* key) {
  if (!object.is_object()) throw ApiError(400, "invalid_body", "the body must be a JSON object");
  const auto it = object.find(key);
  if (it == object.end() || it->is_null()) {
    throw ApiError(400, "missing_field", std::string("'") + key + "' is required");
  }
  return *it;
}

double finite_number(const nlohmann::json& value, const char* key, double min, double max) {
  if (!value.is_number()) invalid(key, "must be a number");
  const double number = value.get<double>();
  if (!std::isfinite(number)) invalid(key, "must be finite");
  if (number < min || number > max) {
    invalid(key, "must be within [" + nlohmann::json(min).dump() + ", " +
                     nlohmann::json(max).dump() + "]");
  }
  return number;
}

}  // namespace

nlohmann::json parse_json_body(std::string_view body) {
  try {
    nlohmann::json parsed = nlohmann::json::parse(body);
    if (!parsed.is_object()) throw ApiError(400, "invalid_body", "the body must be a JSON object");
    return parsed;
  } catch (const nlohmann::json::exception& error) {
    // parse_error, and out_of_range for numbers beyond a double (1e999).
    throw ApiError(400, "malformed_json",
                   std::string("the body is not valid JSON: ") + error.what());
  }
}

double require_number(const nlohmann::json& object, const char* key, double min, double max) {
  return finite_number(field(object, key), key, min, max);
}

std::optional<double> optional_number(const nlohmann::json& object, const char* key, double min,
                                      double max) {
  if (!object.contains(key) || object[key].is_null()) return std::nullopt;
  return finite_number(object[key], key, min, max);
}

std::optional<int> optional_integer(const nlohmann::json& object, const char* key, int min,
                                    int max) {
  if (!object.contains(key) || object[key].is_null()) return std::nullopt;
  const auto& value = object[key];
  const auto within =
      "must be a whole number within [" + std::to_string(min) + ", " + std::to_string(max) + "]";
  if (!value.is_number_integer()) invalid(key, within);
  const auto number = value.get<std::int64_t>();
  if (number < min || number > max) invalid(key, within);
  return static_cast<int>(number);
}

std::string require_string(const nlohmann::json& object, const char* key, std::size_t max_length) {
  const auto& value = field(object, key);
  if (!value.is_string()) invalid(key, "must be a string");
  const std::string text = value.get<std::string>();
  if (text.empty() || text.size() > max_length) {
    invalid(key, "must have 1 to " + std::to_string(max_length) + " characters");
  }
  return text;
}

std::optional<bool> optional_bool(const nlohmann::json& object, const char* key) {
  if (!object.contains(key) || object[key].is_null()) return std::nullopt;
  if (!object[key].is_boolean()) invalid(key, "must be true or false");
  return object[key].get<bool>();
}

bool require_bool(const nlohmann::json& object, const char* key) {
  const auto& value = field(object, key);
  if (!value.is_boolean()) invalid(key, "must be true or false");
  return value.get<bool>();
}

geometry::Pose2D parse_pose(const nlohmann::json& object, bool theta_required) {
  geometry::Pose2D pose;
  pose.x = require_number(object, "x", -kMaxCoordinate_m, kMaxCoordinate_m);
  pose.y = require_number(object, "y", -kMaxCoordinate_m, kMaxCoordinate_m);
  constexpr double kTwoPi = 2 * std::numbers::pi;
  if (theta_required) {
    pose.theta = require_number(object, "theta", -kTwoPi, kTwoPi);
  } else {
    pose.theta = optional_number(object, "theta", -kTwoPi, kTwoPi).value_or(0.0);
  }
  pose.theta = geometry::wrap_angle(pose.theta);
  return pose;
}

geometry::Pose2D require_pose(const nlohmann::json& object, const char* key, bool theta_required) {
  const auto& value = field(object, key);
  if (!value.is_object()) invalid(key, "must be an object {\"x\",\"y\",\"theta\"}");
  return parse_pose(value, theta_required);
}

TeleopRequest parse_teleop(const nlohmann::json& body) {
  TeleopRequest request;
  // Out-of-limit speeds are clamped by the robot, but absurd ones are refused as input errors.
  request.twist.linear_mps = require_number(body, "v", -100.0, 100.0);
  request.twist.angular_radps = require_number(body, "w", -100.0, 100.0);
  if (const auto ttl = optional_number(body, "ttl_ms", 50.0, 1000.0)) {
    request.ttl_ms = static_cast<int>(std::lround(*ttl));
  }
  return request;
}

}  // namespace mobot::api
