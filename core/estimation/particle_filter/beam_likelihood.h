#pragma once

#include <cstddef>
#include <memory>
#include <numbers>
#include <span>
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
  // AMCL's laser_max_range: beams at or beyond min(this, the scan's range_max_m) end nowhere
  // the model can score (AMCL skips them; see no_return_beams).
  double range_max_m = 6.0;
  // A beam that returned nothing within that range still says its ray crossed free space.
  // AMCL throws this away; kept, a pose whose map puts a wall across such a ray scores the beam
  // as a miss. Without it a robot carried down a corridor and facing its open length fits just
  // as well at the corridor's end facing the end wall: the beams that would tell the two apart
  // are exactly the ones that return nothing.
  bool no_return_beams = true;
  // The free part of such a ray stops this far short of the range (range noise, and a wall
  // just beyond the range that the particle's small pose error brings just inside it).
  double no_return_margin_m = 0.3;
  // Only beams whose neighbours this far either side returned nothing either: at the edge of an
  // open sector a ray runs nearly along a wall, where a wall drawn a cell off in the map moves
  // the point the ray meets it by metres, and the true pose would score as a miss (on the office
  // tour's map, tracking RMSE 0.043 m with every such beam, 0.012-0.024 m without them).
  double no_return_clearance_rad = 3.0 * std::numbers::pi / 180.0;
  // What such a ray counts for against a return (its log p, or p^3, times this). Clear or
  // blocked, a ray's score jumps where a return's p slides, and at full weight a handful of rays
  // outvote the returns near the truth. On the office tour's map (3 seeds of tracking, 10 of the
  // corridor kidnap): without the rays RMSE 0.012-0.024 m and 4 of 6 kidnaps found within 30 s;
  // weight 1: 0.026-0.031 m, 10 of 10 (4-19 s); 0.5: 0.020-0.026 m, 10 of 10 (3-18 s); 0.3:
  // 0.017-0.025 m, 9 of 10.
  double no_return_weight = 0.5;
  // At most this many of them, evenly spread over those of the thinned scan: each costs a walk
  // along its ray where a return costs one look-up. Down a corridor a handful is all there is.
  int max_no_return_beams = 10;
};

// The beams of one scan the model uses: their end points in the base frame (sensor_in_base
// applied), the rays of the beams that returned nothing (from the sensor to where their free
// part ends), and the constant z_rand / range_max term.
struct PreparedScan {
  std::vector<geometry::Point2D> endpoints_in_base;
  double rand_term = 0.0;
  geometry::Point2D sensor_in_base;
  std::vector<geometry::Point2D> free_ray_ends_in_base;

  // Without a return there is nothing to weigh: a scan of free rays alone is more likely a
  // blinded sensor than an empty building.
  bool empty() const { return endpoints_in_base.empty(); }
  std::size_t beam_count() const { return endpoints_in_base.size() + free_ray_ends_in_base.size(); }
};

// docs/algorithms.md E4: AMCL's likelihood-field laser models. A beam ending at distance d from
// the nearest obstacle has p = z_hit exp(-d^2 / (2 sigma_hit^2)) + z_rand / range_max (AMCL leaves
// the Gaussian unnormalised); a beam without a return has the p of a hit (d = 0) when its free
// ray crosses no occupied cell of the map, and of a miss (z_rand / range_max) when it does; the
// beams combine as options.combination says.
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
  // The same, except that for kProduct a pose whose value stays below `negligible_below` even
  // with every free ray clear gets them as blocked without walking them: its value is then at
  // most that bound, and a filter that passes its best value less 40 keeps nothing of such a
  // pose anyway (a weight below e^-40 of the best). Most of a global cloud is such poses.
  double log_likelihood(const PreparedScan& scan, const geometry::Pose2D& base_in_map,
                        double negligible_below) const;
  // Whether the segment between two map-frame points crosses no occupied cell of the map (off
  // the grid counts as free; passing within a cell of one counts as crossing it). Walks the
  // distance field: each step is as long as the field guarantees free, so a ray down a corridor
  // takes a handful of look-ups.
  bool segment_free(geometry::Point2D from_in_map, geometry::Point2D to_in_map) const;
  // How well the beams agree with the map on average, from a log_likelihood over `beams` beams
  // (PreparedScan::beam_count):
  // the mean p^3 (kCubedSum) or the geometric mean p (kProduct). Comparable between scans with
  // different numbers of usable beams (augmented MCL's averages need that).
  double beam_agreement(double log_likelihood, std::size_t beams) const;

  // Throws std::invalid_argument when the options are out of range (see the constructor).
  static void validate(const BeamLikelihoodOptions& options);

 private:
  std::shared_ptr<const LikelihoodField> field_;
  BeamLikelihoodOptions options_;
  double beam_term(double hit_term, double rand_term) const;
  // A free ray being walked through the grid, in cells: from (x0, y0) along the unit (ux, uy),
  // t of length done.
  struct RayWalk {
    double x0, y0, ux, uy, length, t;
  };
  static constexpr std::size_t kRaysWalkedTogether = 16;
  // False (nothing to walk) for a non-finite or empty segment.
  static bool start_walk(double x0, double y0, double x1, double y1, RayWalk& walk);
  // How many of the rays meet an occupied cell; the walks are used up.
  std::size_t count_blocked(std::span<RayWalk> walks) const;
  // segment_free() in the grid's frame, in cells.
  bool segment_free_cells(double x0, double y0, double x1, double y1) const;

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
