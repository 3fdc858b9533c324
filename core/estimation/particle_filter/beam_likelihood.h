#pragma once

#include <memory>
#include <vector>

#include "core/estimation/particle_filter/likelihood_field.h"
#include "core/geometry/pose2d.h"
#include "core/msgs/laser_scan.h"

namespace mobot::estimation {

// How the beams' probabilities make a pose's likelihood (AMCL's laser_model_type).
enum class BeamCombination {
  // likelihood_field: AMCL's ad-hoc 1 + sum p^3. Tolerant of unmapped obstacles (no beam can
  // veto a pose), but flat: a pose 0.1 m off keeps three quarters of the true pose's weight.
  kCubedSum,
  // likelihood_field_prob (without beam skipping): the product of the beams' p, Probabilistic
  // Robotics' likelihood_field_range_finder_model. Sharp: the same pose keeps a few per mille.
  kProduct,
};

struct BeamLikelihoodOptions {
  BeamCombination combination = BeamCombination::kProduct;
  // AMCL's laser_max_beams: the scan is thinned to this many beams, evenly spread over it.
  int max_beams = 60;
  // The mixture of the likelihood-field model (laser_z_hit, laser_z_rand, laser_sigma_hit).
  double z_hit = 0.5;
  double z_rand = 0.5;
  double sigma_hit_m = 0.2;
  // kProduct only: the product of the beams' p is raised to this power. 1 is AMCL's; below 1 it
  // counts the beams as fewer independent measurements than they are (neighbouring beams on one
  // wall share its mapping error), which keeps a lucky particle from outweighing a whole cloud.
  double product_exponent = 1.0;
  // AMCL's laser_max_range: beams at or beyond min(this, the scan's range_max_m) are skipped.
  double range_max_m = 6.0;
};

// The beams of one scan the model uses: their end points in the base frame (sensor_in_base
// applied) and the constant z_rand / range_max term.
struct PreparedScan {
  std::vector<geometry::Point2D> endpoints_in_base;
  double rand_term = 0.0;

  bool empty() const { return endpoints_in_base.empty(); }
};

// docs/algorithms.md E4: AMCL's likelihood-field laser models. A beam ending at distance d from
// the nearest obstacle has p = z_hit exp(-d^2 / (2 sigma_hit^2)) + z_rand / range_max (AMCL leaves
// the Gaussian unnormalised); the beams combine as options.combination says.
class BeamLikelihood {
 public:
  // Throws std::invalid_argument for a null field or an option out of range (max_beams < 2,
  // a negative weight, a non-positive sigma or range).
  BeamLikelihood(std::shared_ptr<const LikelihoodField> field,
                 const BeamLikelihoodOptions& options = {});

  const BeamLikelihoodOptions& options() const { return options_; }
  const LikelihoodField& field() const { return *field_; }

  // Thins the scan and drops the beams AMCL ignores: NaN, at or below range_min (AMCL maps them
  // to max range), at or beyond the effective range_max. A scan with no usable beam, bad angles
  // or a non-finite mounting gives an empty result.
  PreparedScan prepare(const msgs::LaserScan& scan) const;

  // The log of the pose's likelihood for the base at `base_in_map`: log(1 + sum p^3) or
  // sum log p. An empty scan or a non-finite pose gives the value of a scan without beams (0).
  double log_likelihood(const PreparedScan& scan, const geometry::Pose2D& base_in_map) const;
  // How well the beams agree with the map on average, from a log_likelihood over `beams` beams:
  // the mean p^3 (kCubedSum) or the geometric mean p (kProduct). Comparable between scans with
  // different numbers of usable beams (augmented MCL's averages need that).
  double beam_agreement(double log_likelihood, std::size_t beams) const;

  // Throws std::invalid_argument when the options are out of range (see the constructor).
  static void validate(const BeamLikelihoodOptions& options);

 private:
  std::shared_ptr<const LikelihoodField> field_;
  BeamLikelihoodOptions options_;
  double beam_term(double hit_term, double rand_term) const;

  // z_hit exp(-d^2 / 2 sigma^2) per cell, and for the points off the grid.
  std::vector<float> hit_term_;
  double off_grid_hit_term_ = 0.0;
  // p^3 or log p per cell for the usual rand term (z_rand / options.range_max_m), so a beam
  // costs a look-up; a scan with a shorter range_max takes the slow path.
  double table_rand_term_ = 0.0;
  std::vector<float> beam_term_;
  double off_grid_beam_term_ = 0.0;
  geometry::Pose2D grid_from_map_;
};

}  // namespace mobot::estimation
