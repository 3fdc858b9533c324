#pragma once

namespace mobot::estimation {

// What a filter did with one predict or update call. Anything but kApplied left the state and
// covariance exactly as they were.
enum class UpdateStatus {
  kApplied,
  kRejectedNonFinite,  // an input was NaN or infinite, or a parameter out of its domain
  kNoMatch,            // nothing observed could be associated with the map
  kRejectedOutlier,    // the innovation failed its gate
  kNumericalFailure,   // the innovation covariance was not positive definite
};

struct UpdateReport {
  UpdateStatus status = UpdateStatus::kApplied;
  // Scalar measurement rows fused.
  int rows_used = 0;
  // Normalised innovation squared nu^T S^-1 nu of what was fused (or of what was gated out);
  // chi-square with rows_used degrees of freedom when the filter is consistent.
  double nis = 0.0;

  bool applied() const { return status == UpdateStatus::kApplied; }

  static UpdateReport rejected(UpdateStatus why) {
    UpdateReport report;
    report.status = why;
    return report;
  }
};

const char* to_string(UpdateStatus status);

}  // namespace mobot::estimation
