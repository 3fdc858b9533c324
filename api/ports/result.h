#pragma once

#include <functional>
#include <utility>
#include <variant>

#include "api/ports/domain_error.h"

namespace mobot::api {

// Nothing to return: the request was carried out.
struct Done {};

// The outcome of a request answered later: a value or the reason it was refused.
template <class T>
class Result {
 public:
  Result(T value) : outcome_(std::move(value)) {}            // NOLINT(google-explicit-constructor)
  Result(DomainError error) : outcome_(std::move(error)) {}  // NOLINT(google-explicit-constructor)

  bool ok() const { return std::holds_alternative<T>(outcome_); }
  const T& value() const { return std::get<T>(outcome_); }
  T& value() { return std::get<T>(outcome_); }
  const DomainError& error() const { return std::get<DomainError>(outcome_); }

 private:
  std::variant<T, DomainError> outcome_;
};

// Called exactly once, from any thread, when a request that waits (on the control loop, a plan,
// a commit) is done. It must not block: it hands the result to whoever replies.
template <class T>
using Completion = std::function<void(Result<T>)>;

}  // namespace mobot::api
