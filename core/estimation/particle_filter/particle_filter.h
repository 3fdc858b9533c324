#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <span>
#include <vector>

#include "core/estimation/particle_filter/beam_likelihood.h"
#include "core/estimation/particle_filter/free_space_sampler.h"
#include "core/estimation/particle_filter/kld_sampler.h"
#include "core/estimation/particle_filter/likelihood_field.h"
#include "core/estimation/particle_filter/odometry_motion_model.h"
#include "core/estimation/weighted_pose.h"
#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"
#include "core/msgs/laser_scan.h"

namespace mobot::estimation {

struct ParticleFilterOptions {
  OdometryMotionModelOptions motion;
  LikelihoodFieldOptions field;
  BeamLikelihoodOptions laser;
  KldSamplerOptions kld;
  // The filter moves, weighs and resamples on the first scan after the odometry has moved this
  // far since the last update (the Dashgo thesis' AMCL update_min_d / update_min_a). Updating a
  // standing robot would resample away the spread without new evidence.
  double update_min_translation_m = 0.25;
  double update_min_rotation_rad = 0.2;
  // Resample on every n-th update only (AMCL's resample_interval); in between the weights of
  // successive scans multiply.
  int resample_interval = 1;
  // Augmented MCL (Probabilistic Robotics Table 8.3, AMCL's recovery_alpha_slow / _fast): short-
  // and long-term averages of the scan likelihood; when the short one drops below the long one,
  // 1 - w_fast / w_slow times global_particles poses from the free space join the resampled cloud
  // (the global density: a share of the tracking cloud leaves a kidnapped robot unfound).
  // AMCL suggests 0.001 for alpha_slow; the averages start at the first scan after an
  // initialisation, and after a global start that scan fits the spread cloud poorly, so at 0.001
  // w_slow stays near that low value for a thousand updates, and a kidnap in the first hour
  // injects nothing until w_fast has fallen below it (the simulated Dashgo's corridor kidnap:
  // recovered in 6-29 s of driving over 10 seeds; with 0.01, 3-15 s).
  double alpha_slow = 0.01;
  double alpha_fast = 0.1;
  // No injection while 1 - w_fast / w_slow stays below this: tracking, the two averages cross
  // back and forth by a few per cent from scan to scan, and each crossing would add hundreds of
  // random particles to weigh for nothing.
  double recovery_min_fraction = 0.05;
  // The prior probability, per update, that the robot was carried off. The random particles are
  // drawn at the rate above but weighted by this prior over that rate (importance sampling from
  // a mixture proposal), so they explore without outvoting the cloud unless the scan fits them
  // overwhelmingly better (a kidnap) rather than a little better (an ambiguous corridor). Too
  // small, and a hypothesis near the truth never gathers the scans it needs against a wrong one
  // that fits almost as well: the office corridor kidnap, 10 seeds, with 1e-4 took up to 30 s
  // of driving (the cloud 2 m down the corridor from the truth for 20 s), with 1e-3 one seed
  // was never found, with 1e-2 all within 16 s. Injection only starts when the fit has dropped
  // (recovery_min_fraction), so tracking never pays for the larger prior.
  double kidnap_probability = 0.01;
  // converged(): the heaviest cluster carries at least this share of the weight, its position
  // (largest axis) and heading standard deviations are below these, and the last scan moved the
  // estimate away from where the odometry carried it by less than them (a tight cloud that still
  // jumps is not settled: a sharp likelihood makes a cloud tight in one scan, right or wrong).
  double converged_min_cluster_weight = 0.9;
  double converged_position_std_m = 0.15;
  double converged_heading_std_rad = 0.1;
  // ... at this many consecutive scan updates: one scan can make a global cloud tight in the
  // wrong place.
  int converged_min_updates = 10;
  // Global localization draws this many particles over the free space; the first resampling
  // brings the cloud back to the KLD count (at most max_particles). A building's free space in
  // poses is large: 5000 particles over the 250 m^2 of the simulated office put less than one
  // within 0.2 m and 0.1 rad of the robot, and the cloud then settles on whichever place fits
  // the scan next best (a room 10 m down the corridor). The one weighing of the dense cloud costs
  // about ten times a tracking update (BENCHMARKS.md).
  std::size_t global_particles = 50000;
  // From a global start until the filter first converges, each scan's likelihood is raised to
  // this power (tempered). Scans of 60 beams whose errors are far from independent make a sharp
  // likelihood: in the first weighing of the global cloud the one particle nearest its pose takes
  // nearly all the weight, so in a building whose two ends look alike (the simulated office's
  // corridor) the hypothesis that survives is the luckier draw, not the better fit, and the
  // other is gone before the robot sees what tells them apart (converged 14.8 m off, turned
  // round at the corridor's other end, on 1 of 20 seeds of the office tour; once in CI). Tempered,
  // both keep a share through the first weighings (the unit test's twin poses). With 0.2: 20 of
  // 20 right, converged after 4.3-5.6 s of driving (4.3-4.7 untempered); 0.1: 20 of 20, 4.7-8.9 s.
  double global_search_exponent = 0.2;
  // A particle where the map has no room for the robot (an occupied or never observed cell, off
  // the grid) has its log-likelihood lowered by this: the robot cannot stand in a wall. AMCL
  // weighs such a particle by its beams alone, and a cloud the odometry carries through a wall
  // (a kidnapped robot driving on where its belief has a wall) fits the scan no worse beyond it
  // than before, so nothing drew the random particles in; the simulated Dashgo's belief sat 0.1 m
  // outside the office for ten seconds.
  double off_map_log_penalty = 20.0;
  // At most this many particles are moved and weighed per call of update(); a larger cloud
  // (global localization, the update after a recovery's injection) is done over successive calls
  // with the scan that started it, the scans meanwhile unused. The call is the control loop's
  // tick: 50 000 particles at once are about 27 ms, more than a period of the Dashgo's 50 Hz
  // loop; 5000 are about 4 ms. 0: the whole cloud in one call (offline, on a log).
  std::size_t max_weighed_per_update = 5000;
  std::uint64_t seed = 1;
};

// The map as the filter reads it, prepared once per map (the distance transform is the costly
// part). A null field: no map.
struct ParticleFilterMap {
  std::shared_ptr<const LikelihoodField> field;
  std::shared_ptr<const FreeSpaceSampler> free_space;
};
ParticleFilterMap prepare_particle_filter_map(const mapping::OccupancyGrid& grid,
                                              const LikelihoodFieldOptions& options = {});

// What one call of ParticleFilter::update did.
enum class FilterUpdate {
  kUpdated,        // moved, weighed with the scan, resampled
  kPredicted,      // no map: the particles moved with the odometry only (dead reckoning)
  kWaiting,        // not moved enough, or no scan yet: nothing changed
  kNoUsableBeams,  // the scan had no beam the model uses: nothing changed
  kRejected,       // non-finite odometry: nothing changed
  kWeighing,       // a part of a large cloud weighed (max_weighed_per_update): no estimate yet
};

// docs/algorithms.md E4: Monte Carlo localization as AMCL does it: the odometry motion model,
// the likelihood-field laser model, KLD-adaptive low-variance resampling and augmented-MCL
// recovery. Odometry comes in as odom-frame poses; the filter samples the motion between the
// pose at its last update and the current one. Deterministic for options.seed.
class ParticleFilter {
 public:
  // Throws std::invalid_argument for an option out of range. Starts with min_particles at the
  // origin and no map.
  explicit ParticleFilter(const ParticleFilterOptions& options = {});

  const ParticleFilterOptions& options() const { return options_; }

  // A null field removes the map: the filter then only predicts.
  void set_map(ParticleFilterMap map);
  bool has_map() const { return laser_ != nullptr; }

  // max_particles drawn from N(pose, covariance), taken at odometry `odom_pose`; the next scan
  // updates the filter whatever the motion. False and nothing changed for a non-finite pose or a
  // covariance that is not symmetric positive semi-definite.
  bool initialize(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance,
                  const geometry::Pose2D& odom_pose);
  // Global localization: global_particles uniform over the map's free space. False and nothing
  // changed without a map or without free cells.
  bool initialize_global(const geometry::Pose2D& odom_pose);

  // One step with the odometry pose now and the scan taken now (or null). See FilterUpdate.
  // While a weighing is spread over calls, each call weighs the next part and the scan is unused.
  FilterUpdate update(const geometry::Pose2D& odom_pose, const msgs::LaserScan* scan);
  // Whether a weighing spread over calls is under way.
  bool weighing() const { return pending_.has_value(); }

  // The pose of the estimate at the last update moved by the odometry since: what a caller
  // reports between updates. Non-finite odometry gives the last estimate.
  geometry::Pose2D pose_at(const geometry::Pose2D& odom_pose) const;
  // The mean of the heaviest cluster at the last update (AMCL's published pose).
  const geometry::Pose2D& estimate() const { return estimate_; }
  // The heaviest cluster's covariance when it carries converged_min_cluster_weight of the
  // weight, else the whole cloud's: one hypothesis reports its own spread, several their union.
  const Eigen::Matrix3d& covariance() const { return covariance_; }
  // A map, at least one scan update since the last initialisation, and the rule of the options.
  bool converged() const;

  // While a weighing is spread over calls, the particles not yet reached are where the last
  // update left them.
  std::span<const WeightedPose> particles() const { return particles_; }
  std::size_t cluster_count() const { return cluster_count_; }
  double heaviest_cluster_weight() const { return heaviest_cluster_weight_; }
  // Scan updates since construction, and the beams the last one used.
  std::uint64_t sensor_updates() const { return sensor_updates_; }
  std::size_t last_beam_count() const { return last_beam_count_; }
  // The augmented-MCL state: the averages and the share of random particles in the last draw.
  double w_slow() const { return w_slow_; }
  double w_fast() const { return w_fast_; }
  double last_random_fraction() const { return last_random_fraction_; }
  // How far the last scan moved the estimate from the odometry's prediction.
  double last_correction_m() const { return last_correction_m_; }
  double last_correction_rad() const { return last_correction_rad_; }

 private:
  bool moved_enough(const geometry::Pose2D& odom_pose) const;
  // The power the scans' likelihood is raised to now (global_search_exponent while searching).
  double likelihood_exponent() const;
  // The convergence rule at the last update, before the count of consecutive updates.
  bool settled_now() const;
  void move_particles(const geometry::Pose2D& odom_pose);
  // Ends a weighing under way unfinished, moving the particles it had not reached.
  void abandon_weighing();
  // The next part of the pending weighing; when it was the last, resamples and reports.
  FilterUpdate continue_weighing();
  // `best`: the largest of log_likelihoods_, kept by the weighing.
  void resample_weighed(const PreparedScan& scan, double best);
  void finish_update(const geometry::Pose2D& predicted, std::size_t beams);
  // Adds random_fraction x global_particles poses from the free space, weighted by the kidnap
  // prior (see the options), to the resampled cloud.
  void inject_random_particles(double random_fraction);
  // Clusters, estimate, covariance from the current particles.
  void refresh_statistics();
  void start_over(const geometry::Pose2D& odom_pose);
  void restart_fit_averages();

  ParticleFilterOptions options_;
  OdometryMotionModel motion_;
  KldSampler sampler_;
  ParticleFilterMap map_;
  std::unique_ptr<BeamLikelihood> laser_;
  std::mt19937_64 rng_;

  std::vector<WeightedPose> particles_;
  // A weighing under way: the scan, the motion, where the estimate would have been without it,
  // and how far it got (the particles up to there are moved and their values are in
  // log_likelihoods_, best the largest).
  struct PendingWeighing {
    PreparedScan scan;
    OdometryStep step;  // the motion the particles not yet weighed have still to make
    geometry::Pose2D predicted;
    std::size_t weighed = 0;
    double best = 0.0;
  };
  std::optional<PendingWeighing> pending_;
  std::vector<double> log_likelihoods_;
  // The odometry pose the particles were last moved to; unset until the first call anchors it.
  std::optional<geometry::Pose2D> odom_at_particles_;
  geometry::Pose2D estimate_;
  geometry::Pose2D odom_at_estimate_;
  Eigen::Matrix3d covariance_ = Eigen::Matrix3d::Zero();
  bool force_update_ = true;
  // From initialize_global() until the first convergence: the scans' likelihood is tempered.
  bool global_search_ = false;
  std::uint64_t updates_since_start_ = 0;
  std::uint64_t settled_updates_ = 0;
  std::uint64_t weighings_ = 0;
  std::uint64_t sensor_updates_ = 0;
  std::size_t last_beam_count_ = 0;
  std::size_t cluster_count_ = 1;
  double heaviest_cluster_weight_ = 1.0;
  Eigen::Matrix3d heaviest_covariance_ = Eigen::Matrix3d::Zero();
  double w_slow_ = 0.0;
  double w_fast_ = 0.0;
  double last_random_fraction_ = 0.0;
  double last_correction_m_ = 0.0;
  double last_correction_rad_ = 0.0;
};

}  // namespace mobot::estimation
