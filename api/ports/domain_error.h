#pragma once

#include <stdexcept>
#include <string>

namespace mobot::api {

// What kind of refusal a request met, in the robot's terms; api/ maps each kind to an HTTP
// status, so the runtime never needs to know one.
enum class ErrorKind {
  kInvalid,     // malformed or out of range
  kNotFound,    // an unknown id
  kConflict,    // conflicts with the robot's state (e-stop engaged, a sweep running)
  kImpossible,  // well-formed but cannot be done (no path, goal in an obstacle)
};

struct DomainError {
  ErrorKind kind = ErrorKind::kInvalid;
  std::string code;  // snake_case, part of the contract
  std::string message;
};

// A refused request from a port method that answers at once. Whoever throws it has changed
// nothing.
class DomainException : public std::runtime_error {
 public:
  explicit DomainException(DomainError error)
      : std::runtime_error(error.message), error_(std::move(error)) {}
  DomainException(ErrorKind kind, std::string code, const std::string& message)
      : DomainException(DomainError{kind, std::move(code), message}) {}

  const DomainError& error() const { return error_; }

 private:
  DomainError error_;
};

}  // namespace mobot::api
