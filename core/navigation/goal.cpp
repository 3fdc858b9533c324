#include "core/navigation/goal.h"

namespace mobot::navigation {

std::string_view to_string(GoalStatus status) {
  switch (status) {
    case GoalStatus::kPlanning:
      return "planning";
    case GoalStatus::kActive:
      return "active";
    case GoalStatus::kSucceeded:
      return "succeeded";
    case GoalStatus::kFailed:
      return "failed";
    case GoalStatus::kCanceled:
      return "canceled";
  }
  return "unknown";
}

}  // namespace mobot::navigation
