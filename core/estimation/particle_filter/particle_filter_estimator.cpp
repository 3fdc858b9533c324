#include "core/estimation/particle_filter/particle_filter_estimator.h"

#include <cmath>

#include "core/kinematics/diff_drive.h"

namespace mobot::estimation {

ParticleFilterEstimator::ParticleFilterEstimator(const ParticleFilterEstimatorOptions& options)
    : options_(options), filter_(options.filter) {}

void ParticleFilterEstimator::reset(const geometry::Pose2D& pose,
                                    const Eigen::Matrix3d& covariance) {
  if (!filter_.initialize(pose, covariance, odom_)) ++counters_.rejected_updates;
}

void ParticleFilterEstimator::set_map(std::shared_ptr<const MapModel> map) {
  if (!map || !map->grid || map->grid->cells().empty()) {
    grid_.reset();
    filter_.set_map({});
    return;
  }
  if (map->grid == grid_) return;
  grid_ = map->grid;
  // The model's field when it was built with this filter's options (off the control loop), else
  // built here.
  if (map->likelihood_field && map->free_space &&
      map->likelihood_field->max_distance_m() == options_.filter.field.max_distance_m) {
    filter_.set_map({map->likelihood_field, map->free_space});
    return;
  }
  filter_.set_map(prepare_particle_filter_map(*grid_, options_.filter.field));
}

void ParticleFilterEstimator::update(const EstimatorInputs& inputs) {
  if (inputs.travel) {
    const WheelTravel& travel = *inputs.travel;
    if (std::isfinite(travel.left_m) && std::isfinite(travel.right_m) &&
        std::isfinite(inputs.track_m) && inputs.track_m > 0.0) {
      odom_ =
          kinematics::integrate_wheel_travel(odom_, travel.left_m, travel.right_m, inputs.track_m);
    } else {
      ++counters_.rejected_updates;
    }
  }
  const FilterUpdate outcome = filter_.update(odom_, inputs.scan);
  if (outcome == FilterUpdate::kUpdated) {
    ++counters_.scan_updates;
    counters_.features_matched += filter_.last_beam_count();
  } else if (outcome == FilterUpdate::kNoUsableBeams || outcome == FilterUpdate::kRejected) {
    ++counters_.rejected_updates;
  }
}

bool ParticleFilterEstimator::start_global_localization() {
  return filter_.initialize_global(odom_);
}

std::vector<WeightedPose> ParticleFilterEstimator::particles(std::size_t max_count) const {
  const auto all = filter_.particles();
  if (max_count == 0 || all.empty()) return {};
  const std::size_t stride = (all.size() + max_count - 1) / max_count;
  std::vector<WeightedPose> out;
  out.reserve(all.size() / stride + 1);
  double total = 0.0;
  for (std::size_t i = 0; i < all.size(); i += stride) {
    out.push_back(all[i]);
    total += all[i].weight;
  }
  if (total > 0.0) {
    for (WeightedPose& particle : out) particle.weight /= total;
  }
  return out;
}

}  // namespace mobot::estimation
