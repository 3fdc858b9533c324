#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "core/geometry/pose2d.h"
#include "core/slam/probability_grid.h"

namespace mobot::slam {

struct CorrelativeSearchOptions {
  // Half-widths of the search window around the initial pose.
  double linear_window_m = 0.25;
  double angular_window_rad = 0.26;
  // Angular step. 0: Cartographer's choice, the step that moves the farthest point by one cell,
  // acos(1 - res^2 / (2 r_max^2)).
  double angular_step_rad = 0.0;
  // Candidates whose score cannot reach this are never expanded; no match at all (nullopt) when the
  // best stays below it.
  double min_score = 0.0;
  // Covariance from the response (Olson 2009 §IV-B): the full-resolution scores within this many
  // cells and angular steps of the best are weighted by exp(-(best - score) / temperature).
  int covariance_half_cells = 3;
  int covariance_half_steps = 3;
  double covariance_temperature = 0.02;
};

struct CorrelativeMatch {
  geometry::Pose2D pose;  // the base in the grid's (map) frame
  double score = 0.0;     // mean grid value under the points, 0..1
  // Of (x, y, theta) around `pose`, from the response; floored at a quarter cell / step.
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
};

// docs/algorithms.md E5: real-time correlative scan matching (Olson 2009) made exhaustive-but-fast
// by branch and bound over a stack of max-pooled grids (Cartographer's
// FastCorrelativeScanMatcher2D): level h holds in each cell the maximum of the 2^h x 2^h cells
// above-right of it, so a candidate's score at level h bounds every finer candidate it covers. The
// result is the best pose on the search lattice (cells x angular steps), exactly as a brute-force
// search would find it.
class CorrelativeScanMatcher {
 public:
  // Precomputes the levels for windows up to `max_linear_window_m` (a wider window asked of match()
  // is clipped to it). Cells are stored as bytes (Cartographer's precomputation grids do the same):
  // a quarter of the memory traffic, and the bound stays exact on the quantised values. Throws
  // std::invalid_argument on a negative or non-finite window.
  CorrelativeScanMatcher(const ProbabilityGrid& grid, double max_linear_window_m);

  // The best pose of the base with `points_in_base` within the window around `initial_pose`, or
  // nullopt for no points, an empty grid, a non-finite pose, or no candidate reaching min_score.
  // Throws std::invalid_argument on negative or non-finite search options.
  std::optional<CorrelativeMatch> match(std::span<const geometry::Point2D> points_in_base,
                                        const geometry::Pose2D& initial_pose,
                                        const CorrelativeSearchOptions& options) const;

  int levels() const { return static_cast<int>(levels_.size()); }

 private:
  struct DiscreteScan {
    double angle_rad = 0.0;
    // Index into the padded levels of each point's cell at offset (0, 0); points whose cell lies
    // outside the grid are dropped (the grid covers what the window can reach).
    std::vector<std::int32_t> cells;
    std::size_t point_count = 0;  // before dropping: scores are means over every point
  };
  struct Candidate {
    int scan = 0;  // index into the discretised scans
    int dx = 0, dy = 0;
    double score = 0.0;
  };

  double score(const DiscreteScan& scan, int level, int dx, int dy) const;
  void search(const std::vector<DiscreteScan>& scans, std::vector<Candidate> candidates, int level,
              int window_cells, double min_score, Candidate& best) const;

  GridLimits limits_;
  int max_window_cells_ = 0;
  int padding_ = 0;  // any grid cell shifted by at most this stays in the padded frame
  int padded_width_ = 0;
  int padded_height_ = 0;
  std::vector<std::vector<std::uint8_t>> levels_;
};

}  // namespace mobot::slam
