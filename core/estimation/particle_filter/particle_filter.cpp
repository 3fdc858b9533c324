#include "core/estimation/particle_filter/particle_filter.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/estimation/particle_filter/particle_clusters.h"
#include "core/estimation/particle_filter/pose_moments.h"
#include "core/numeric/finite.h"

namespace mobot::estimation {
namespace {

void validate(const ParticleFilterOptions& options) {
  BeamLikelihood::validate(options.laser);
  if (!finite_positive(options.field.max_distance_m) ||
      !finite_non_negative(options.update_min_translation_m) ||
      !finite_non_negative(options.update_min_rotation_rad) || options.resample_interval < 1 ||
      !(options.alpha_slow >= 0.0) || !(options.alpha_slow <= 1.0) ||
      !(options.alpha_fast >= 0.0) || !(options.alpha_fast <= 1.0) ||
      !(options.converged_min_cluster_weight > 0.0) ||
      !(options.converged_min_cluster_weight <= 1.0) ||
      !finite_positive(options.converged_position_std_m) ||
      !finite_positive(options.converged_heading_std_rad) || !(options.kidnap_probability >= 0.0) ||
      !(options.kidnap_probability <= 1.0) || !(options.recovery_min_fraction >= 0.0) ||
      !(options.recovery_min_fraction < 1.0) || options.converged_min_updates < 1 ||
      options.global_particles < 1 || !(options.global_search_exponent > 0.0) ||
      !(options.global_search_exponent <= 1.0) ||
      !finite_non_negative(options.off_map_log_penalty)) {
    throw std::invalid_argument("particle filter: option out of range");
  }
}

// The square root of a covariance for sampling (eigen-decomposed, so a rank-deficient one, a
// zero heading variance for example, is fine). Nullopt when not symmetric PSD or not finite.
std::optional<Eigen::Matrix3d> covariance_root(const Eigen::Matrix3d& covariance) {
  if (!covariance.allFinite()) return std::nullopt;
  const double scale = 1.0 + covariance.cwiseAbs().maxCoeff();
  if ((covariance - covariance.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) {
    return std::nullopt;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  if (eigen.info() != Eigen::Success || eigen.eigenvalues().minCoeff() < -1e-12 * scale) {
    return std::nullopt;
  }
  return Eigen::Matrix3d(eigen.eigenvectors() *
                         eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal());
}

}  // namespace

ParticleFilterMap prepare_particle_filter_map(const mapping::OccupancyGrid& grid,
                                              const LikelihoodFieldOptions& options) {
  return {std::make_shared<const LikelihoodField>(grid, options),
          std::make_shared<const FreeSpaceSampler>(grid)};
}

ParticleFilter::ParticleFilter(const ParticleFilterOptions& options)
    : options_(options), motion_(options.motion), sampler_(options.kld), rng_(options.seed) {
  validate(options_);
  const double weight = 1.0 / static_cast<double>(options_.kld.min_particles);
  particles_.assign(options_.kld.min_particles, WeightedPose{{}, weight});
}

void ParticleFilter::set_map(ParticleFilterMap map) {
  // A weighing under way was against the old map: it ends, the particles moved.
  abandon_weighing();
  if (!map.field) {
    map_ = {};
    laser_.reset();
    return;
  }
  laser_ = std::make_unique<BeamLikelihood>(map.field, options_.laser);
  map_ = std::move(map);
  // A new map is new evidence for the same odometry.
  force_update_ = true;
}

bool ParticleFilter::initialize(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance,
                                const geometry::Pose2D& odom_pose) {
  if (!geometry::is_finite(pose) || !geometry::is_finite(odom_pose)) return false;
  const auto root = covariance_root(covariance);
  if (!root) return false;
  std::normal_distribution<double> normal(0.0, 1.0);
  const std::size_t count = options_.kld.max_particles;
  const double weight = 1.0 / static_cast<double>(count);
  particles_.clear();
  particles_.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Eigen::Vector3d d = *root * Eigen::Vector3d(normal(rng_), normal(rng_), normal(rng_));
    particles_.push_back(
        {{pose.x + d.x(), pose.y + d.y(), geometry::wrap_angle(pose.theta + d.z())}, weight});
  }
  start_over(odom_pose);
  global_search_ = false;
  estimate_ = {pose.x, pose.y, geometry::wrap_angle(pose.theta)};
  return true;
}

bool ParticleFilter::initialize_global(const geometry::Pose2D& odom_pose) {
  if (!has_map() || !map_.free_space || map_.free_space->empty() ||
      !geometry::is_finite(odom_pose)) {
    return false;
  }
  const std::size_t count = options_.global_particles;
  const double weight = 1.0 / static_cast<double>(count);
  particles_.clear();
  particles_.reserve(count);
  for (std::size_t i = 0; i < count; ++i)
    particles_.push_back({map_.free_space->sample(rng_), weight});
  start_over(odom_pose);
  global_search_ = true;
  return true;
}

void ParticleFilter::start_over(const geometry::Pose2D& odom_pose) {
  pending_.reset();
  odom_at_particles_ = odom_pose;
  odom_at_estimate_ = odom_pose;
  force_update_ = true;
  updates_since_start_ = 0;
  settled_updates_ = 0;
  restart_fit_averages();
  last_random_fraction_ = 0.0;
  refresh_statistics();
}

FilterUpdate ParticleFilter::update(const geometry::Pose2D& odom_pose,
                                    const msgs::LaserScan* scan) {
  if (!geometry::is_finite(odom_pose)) return FilterUpdate::kRejected;
  if (!odom_at_particles_) {
    odom_at_particles_ = odom_pose;
    odom_at_estimate_ = odom_pose;
  }
  if (!has_map()) {
    if (!moved_enough(odom_pose)) return FilterUpdate::kWaiting;
    // Dead reckoning: the cloud spreads with the motion noise, the estimate stays the odometry's.
    move_particles(odom_pose);
    covariance_ = weighted_pose_moments(particles_).covariance;
    return FilterUpdate::kPredicted;
  }
  if (pending_) return continue_weighing();
  if (scan == nullptr) return FilterUpdate::kWaiting;
  if (!force_update_ && !moved_enough(odom_pose)) return FilterUpdate::kWaiting;
  PreparedScan prepared = laser_->prepare(*scan);
  if (prepared.empty()) return FilterUpdate::kNoUsableBeams;
  const geometry::Pose2D predicted = pose_at(odom_pose);
  // Each particle is moved just before it is weighed, so a large cloud's motion is spread over
  // the calls with its weighing (the same draws in the same order as moving them all first).
  const OdometryStep step = motion_.step(*odom_at_particles_, odom_pose);
  odom_at_particles_ = odom_pose;
  log_likelihoods_.resize(particles_.size());
  pending_ = PendingWeighing{std::move(prepared), step, predicted, 0,
                             -std::numeric_limits<double>::infinity()};
  return continue_weighing();
}

void ParticleFilter::abandon_weighing() {
  if (!pending_) return;
  for (std::size_t i = pending_->weighed; i < particles_.size(); ++i) {
    particles_[i].pose = motion_.sample(pending_->step, particles_[i].pose, rng_);
  }
  pending_.reset();
}

FilterUpdate ParticleFilter::continue_weighing() {
  PendingWeighing& pending = *pending_;
  const std::size_t count = particles_.size();
  const std::size_t chunk = options_.max_weighed_per_update;
  const std::size_t end = chunk == 0 ? count : std::min(count, pending.weighed + chunk);
  // A particle e^-40 below the best so far is nothing the resampling keeps: its free rays need
  // no walk (BeamLikelihood::log_likelihood).
  constexpr double kNegligibleLog = 40.0;
  const double negligible_log = kNegligibleLog / likelihood_exponent();
  const LikelihoodField& field = laser_->field();
  for (std::size_t i = pending.weighed; i < end; ++i) {
    particles_[i].pose = motion_.sample(pending.step, particles_[i].pose, rng_);
    const geometry::Pose2D& pose = particles_[i].pose;
    double value = laser_->log_likelihood(pending.scan, pose, pending.best - negligible_log);
    if (!field.open_at({pose.x, pose.y})) value -= options_.off_map_log_penalty;
    log_likelihoods_[i] = value;
    pending.best = std::max(pending.best, value);
  }
  pending.weighed = end;
  if (end < count) return FilterUpdate::kWeighing;
  const PendingWeighing done = std::move(pending);
  pending_.reset();
  resample_weighed(done.scan, done.best);
  finish_update(done.predicted, done.scan.beam_count());
  return FilterUpdate::kUpdated;
}

void ParticleFilter::finish_update(const geometry::Pose2D& predicted, std::size_t beams) {
  refresh_statistics();
  // The estimate is of the scan's time: the odometry then is where the particles were moved to.
  odom_at_estimate_ = *odom_at_particles_;
  // After an initialisation the "prediction" is the initial guess: the first correction counts.
  last_correction_m_ = std::hypot(estimate_.x - predicted.x, estimate_.y - predicted.y);
  last_correction_rad_ = std::abs(geometry::wrap_angle(estimate_.theta - predicted.theta));
  force_update_ = false;
  ++updates_since_start_;
  settled_updates_ = settled_now() ? settled_updates_ + 1 : 0;
  if (global_search_ && converged()) {
    // The averages so far weighed a cloud spread over the building, which fits any scan poorly:
    // as the long-term "normal" fit, that would hide a kidnap soon after (w_fast falls to the
    // kidnapped fit and stays above it). Tracking starts them afresh.
    global_search_ = false;
    restart_fit_averages();
  }
  ++sensor_updates_;
  last_beam_count_ = beams;
}

void ParticleFilter::restart_fit_averages() { w_slow_ = w_fast_ = 0.0; }

double ParticleFilter::likelihood_exponent() const {
  return global_search_ ? options_.global_search_exponent : 1.0;
}

bool ParticleFilter::moved_enough(const geometry::Pose2D& odom_pose) const {
  const geometry::Pose2D& before = *odom_at_particles_;
  return std::hypot(odom_pose.x - before.x, odom_pose.y - before.y) >=
             options_.update_min_translation_m ||
         std::abs(geometry::wrap_angle(odom_pose.theta - before.theta)) >=
             options_.update_min_rotation_rad;
}

void ParticleFilter::move_particles(const geometry::Pose2D& odom_pose) {
  const OdometryStep step = motion_.step(*odom_at_particles_, odom_pose);
  for (WeightedPose& particle : particles_) {
    particle.pose = motion_.sample(step, particle.pose, rng_);
  }
  odom_at_particles_ = odom_pose;
}

void ParticleFilter::resample_weighed(const PreparedScan& scan, double best) {
  const std::size_t beams = scan.beam_count();
  // Relative to the best particle, so that a product of 60 beams does not underflow.
  const double exponent = likelihood_exponent();
  double total = 0.0;
  double agreement = 0.0;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    WeightedPose& particle = particles_[i];
    particle.weight *= std::exp(exponent * (log_likelihoods_[i] - best));
    total += particle.weight;
    agreement += particle.weight * laser_->beam_agreement(log_likelihoods_[i], beams);
  }
  if (total > 0.0 && std::isfinite(total)) {
    for (WeightedPose& particle : particles_) particle.weight /= total;
    // How well the filter's hypotheses explain this scan: the beams' agreement averaged over
    // the posterior. AMCL averages the likelihood over the prior, which the injected particles
    // themselves pull down; it then resets both averages after every injection, and recovers
    // only as far as one injection reaches.
    const double w_avg = agreement / total;
    w_slow_ = w_slow_ == 0.0 ? w_avg : w_slow_ + options_.alpha_slow * (w_avg - w_slow_);
    w_fast_ = w_fast_ == 0.0 ? w_avg : w_fast_ + options_.alpha_fast * (w_avg - w_fast_);
  } else {
    const double weight = 1.0 / static_cast<double>(particles_.size());
    for (WeightedPose& particle : particles_) particle.weight = weight;
  }
  if (++weighings_ % static_cast<std::uint64_t>(options_.resample_interval) != 0) return;
  const bool can_inject = map_.free_space && !map_.free_space->empty() && w_slow_ > 0.0;
  const double fraction = can_inject ? 1.0 - w_fast_ / w_slow_ : 0.0;
  last_random_fraction_ = fraction >= options_.recovery_min_fraction ? fraction : 0.0;
  particles_ = sampler_.resample(particles_, 0.0, {}, rng_);
  const double r = last_random_fraction_;
  if (r > 0.0) inject_random_particles(r);
}

void ParticleFilter::inject_random_particles(double random_fraction) {
  // Augmented MCL decides how many particles explore, at the density of global localization: a
  // share of global_particles, not of the tracking cloud, which over a building's free space
  // would put about one near a kidnapped robot every 60 updates. Their importance weight keeps
  // the belief honest: the belief gives poses away from the cloud the kidnap prior rho, the
  // proposal drew them with the random fraction r, so together they weigh
  // min(rho / (1 - rho), r / (1 - r)) against the resampled cloud's 1.
  const double r = std::min(random_fraction, 0.99);
  const double rho = options_.kidnap_probability;
  const auto count =
      static_cast<std::size_t>(std::ceil(r * static_cast<double>(options_.global_particles)));
  if (count == 0) return;
  const double random_mass = std::min(rho / (1.0 - rho), r / (1.0 - r));
  const double each = random_mass / static_cast<double>(count);
  double cloud_mass = 0.0;
  for (const WeightedPose& particle : particles_) cloud_mass += particle.weight;
  particles_.reserve(particles_.size() + count);
  for (std::size_t i = 0; i < count; ++i)
    particles_.push_back({map_.free_space->sample(rng_), each * cloud_mass});
  const double total = cloud_mass * (1.0 + random_mass);
  for (WeightedPose& particle : particles_) particle.weight /= total;
}

void ParticleFilter::refresh_statistics() {
  const std::vector<ParticleCluster> clusters = cluster_particles(particles_, options_.kld.bins);
  if (clusters.empty()) return;
  double total = 0.0;
  for (const ParticleCluster& cluster : clusters) total += cluster.moments.weight;
  const ParticleCluster& heaviest = clusters.front();
  cluster_count_ = clusters.size();
  heaviest_cluster_weight_ = total > 0.0 ? heaviest.moments.weight / total : 0.0;
  heaviest_covariance_ = heaviest.moments.covariance;
  covariance_ = heaviest_cluster_weight_ >= options_.converged_min_cluster_weight
                    ? heaviest.moments.covariance
                    : weighted_pose_moments(particles_).covariance;
  estimate_ = heaviest.moments.mean;
}

bool ParticleFilter::converged() const {
  return has_map() && updates_since_start_ > 0 &&
         settled_updates_ >= static_cast<std::uint64_t>(options_.converged_min_updates);
}

bool ParticleFilter::settled_now() const {
  if (!has_map() || updates_since_start_ == 0 ||
      heaviest_cluster_weight_ < options_.converged_min_cluster_weight) {
    return false;
  }
  const Eigen::Matrix2d position = heaviest_covariance_.topLeftCorner<2, 2>();
  if (!heaviest_covariance_.allFinite()) return false;
  const double largest_var_m2 =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(position, Eigen::EigenvaluesOnly)
          .eigenvalues()
          .maxCoeff();
  const double position_std = options_.converged_position_std_m;
  const double heading_std = options_.converged_heading_std_rad;
  return largest_var_m2 < position_std * position_std &&
         heaviest_covariance_(2, 2) < heading_std * heading_std &&
         last_correction_m_ < position_std && last_correction_rad_ < heading_std;
}

geometry::Pose2D ParticleFilter::pose_at(const geometry::Pose2D& odom_pose) const {
  if (!geometry::is_finite(odom_pose)) return estimate_;
  return geometry::compose(estimate_,
                           geometry::compose(geometry::inverse(odom_at_estimate_), odom_pose));
}

}  // namespace mobot::estimation
