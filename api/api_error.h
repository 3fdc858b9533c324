#pragma once

#include <stdexcept>
#include <string>

namespace mobot::api {

// A request the server refuses; it becomes `{"error":{"code","message"}}` with this HTTP status.
// Whoever throws it must not have changed any state.
class ApiError : public std::runtime_error {
 public:
  ApiError(int http_status, std::string code, const std::string& message)
      : std::runtime_error(message), http_status_(http_status), code_(std::move(code)) {}

  int http_status() const { return http_status_; }
  const std::string& code() const { return code_; }

 private:
  int http_status_;
  std::string code_;
};

}  // namespace mobot::api
