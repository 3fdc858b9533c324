#include "core/estimation/update_report.h"

namespace mobot::estimation {

const char* to_string(UpdateStatus status) {
  switch (status) {
    case UpdateStatus::kApplied:
      return "applied";
    case UpdateStatus::kRejectedNonFinite:
      return "rejected_non_finite";
    case UpdateStatus::kNoMatch:
      return "no_match";
    case UpdateStatus::kRejectedOutlier:
      return "rejected_outlier";
    case UpdateStatus::kNumericalFailure:
      return "numerical_failure";
  }
  return "unknown";
}

}  // namespace mobot::estimation
