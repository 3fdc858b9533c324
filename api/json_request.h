#pragma once

#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "core/geometry/pose2d.h"
#include "core/msgs/twist.h"

namespace mobot::api {

// Validation of JSON request bodies. Every failure throws ApiError 400 whose message names the
// field and what was expected, before anything is changed.

nlohmann::json parse_json_body(std::string_view body);

// The largest |x| or |y| a request may name: far beyond any map, near enough for a double's cm.
inline constexpr double kMaxCoordinate_m = 1e6;

double require_number(const nlohmann::json& object, const char* key, double min, double max);
std::optional<double> optional_number(const nlohmann::json& object, const char* key, double min,
                                      double max);
// A whole number (50, not 50.5 nor "50") within [min, max], or nullopt when the key is absent.
std::optional<int> optional_integer(const nlohmann::json& object, const char* key, int min,
                                    int max);
std::string require_string(const nlohmann::json& object, const char* key,
                           std::size_t max_length = 256);
std::optional<bool> optional_bool(const nlohmann::json& object, const char* key);
bool require_bool(const nlohmann::json& object, const char* key);
// {"x","y","theta"?}: positions within +-1e6 m.
geometry::Pose2D require_pose(const nlohmann::json& object, const char* key, bool theta_required);
geometry::Pose2D parse_pose(const nlohmann::json& object, bool theta_required);

struct TeleopRequest {
  msgs::Twist twist;
  int ttl_ms = 300;
};
TeleopRequest parse_teleop(const nlohmann::json& body);

}  // namespace mobot::api
