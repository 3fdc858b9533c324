#include "core/estimation/particle_filter/beam_likelihood.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mobot::estimation {
namespace {

double hit_term(double distance_m, const BeamLikelihoodOptions& options) {
  return options.z_hit *
         std::exp(-(distance_m * distance_m) / (2.0 * options.sigma_hit_m * options.sigma_hit_m));
}

bool non_negative(double value) { return value >= 0.0 && std::isfinite(value); }
bool positive(double value) { return value > 0.0 && std::isfinite(value); }

}  // namespace

BeamLikelihood::BeamLikelihood(std::shared_ptr<const LikelihoodField> field,
                               const BeamLikelihoodOptions& options)
    : field_(std::move(field)), options_(options) {
  if (!field_) throw std::invalid_argument("beam likelihood needs a likelihood field");
  validate(options);
  const auto& distances = field_->distances_m();
  hit_term_.resize(distances.size());
  std::transform(distances.begin(), distances.end(), hit_term_.begin(), [this](float d) {
    return static_cast<float>(hit_term(static_cast<double>(d), options_));
  });
  off_grid_hit_term_ = hit_term(field_->max_distance_m(), options_);
  table_rand_term_ = options_.z_rand / options_.range_max_m;
  beam_term_.resize(hit_term_.size());
  std::transform(hit_term_.begin(), hit_term_.end(), beam_term_.begin(), [this](float hit) {
    return static_cast<float>(beam_term(static_cast<double>(hit), table_rand_term_));
  });
  off_grid_beam_term_ = beam_term(off_grid_hit_term_, table_rand_term_);
  grid_from_map_ = geometry::inverse(field_->origin());
}

double BeamLikelihood::beam_term(double hit_term, double rand_term) const {
  const double pz = hit_term + rand_term;
  if (options_.combination == BeamCombination::kCubedSum) return pz * pz * pz;
  // A floor keeps a beam that fits nowhere (z_rand 0, far from everything) from giving -inf.
  return std::log(std::max(pz, 1e-300));
}

void BeamLikelihood::validate(const BeamLikelihoodOptions& options) {
  if (options.max_beams < 2 || !non_negative(options.z_hit) || !non_negative(options.z_rand) ||
      !positive(options.sigma_hit_m) || !positive(options.range_max_m) ||
      !positive(options.product_exponent) || options.product_exponent > 1.0) {
    throw std::invalid_argument("beam likelihood: option out of range");
  }
}

PreparedScan BeamLikelihood::prepare(const msgs::LaserScan& scan) const {
  PreparedScan prepared;
  const double range_max = std::min(static_cast<double>(scan.range_max_m), options_.range_max_m);
  const double range_min = std::max(static_cast<double>(scan.range_min_m), 0.0);
  const auto count = static_cast<int>(scan.ranges_m.size());
  if (count == 0 || !(range_max > 0.0) || !std::isfinite(scan.angle_min_rad) ||
      !std::isfinite(scan.angle_increment_rad) || !geometry::is_finite(scan.sensor_in_base)) {
    return prepared;
  }
  prepared.rand_term = options_.z_rand / range_max;
  const int beams = std::min(count, options_.max_beams);
  prepared.endpoints_in_base.reserve(static_cast<std::size_t>(beams));
  const double c = std::cos(scan.sensor_in_base.theta);
  const double s = std::sin(scan.sensor_in_base.theta);
  for (int k = 0; k < beams; ++k) {
    // Evenly over the whole scan, first and last beam included.
    const int i =
        beams == 1
            ? 0
            : static_cast<int>(std::lround(static_cast<double>(k) * (count - 1) / (beams - 1)));
    const double range = static_cast<double>(scan.ranges_m[static_cast<std::size_t>(i)]);
    if (!(range > range_min) || !(range < range_max)) continue;  // NaN fails both
    const double bearing =
        static_cast<double>(scan.angle_min_rad) + i * static_cast<double>(scan.angle_increment_rad);
    const double sx = range * std::cos(bearing);
    const double sy = range * std::sin(bearing);
    prepared.endpoints_in_base.push_back(
        {scan.sensor_in_base.x + c * sx - s * sy, scan.sensor_in_base.y + s * sx + c * sy});
  }
  return prepared;
}

double BeamLikelihood::log_likelihood(const PreparedScan& scan,
                                      const geometry::Pose2D& base_in_map) const {
  // Into the grid's frame once per pose, so each beam costs a rotation and a table look-up.
  const geometry::Pose2D base = geometry::compose(grid_from_map_, base_in_map);
  if (!geometry::is_finite(base)) return 0.0;
  const double c = std::cos(base.theta);
  const double s = std::sin(base.theta);
  const double inverse_resolution = 1.0 / field_->resolution_m();
  const int width = field_->width();
  const int height = field_->height();
  const bool tabled = scan.rand_term == table_rand_term_;
  const std::vector<float>& table = tabled ? beam_term_ : hit_term_;
  const double off_grid = tabled ? off_grid_beam_term_ : off_grid_hit_term_;
  double sum = 0.0;
  for (const geometry::Point2D& end : scan.endpoints_in_base) {
    const double gx = (base.x + c * end.x - s * end.y) * inverse_resolution;
    const double gy = (base.y + s * end.x + c * end.y) * inverse_resolution;
    double term = off_grid;
    if (gx >= 0.0 && gy >= 0.0 && gx < width && gy < height) {
      const auto cell =
          static_cast<std::size_t>(static_cast<int>(gy)) * static_cast<std::size_t>(width) +
          static_cast<std::size_t>(static_cast<int>(gx));
      term = static_cast<double>(table[cell]);
    }
    sum += tabled ? term : beam_term(term, scan.rand_term);
  }
  return options_.combination == BeamCombination::kCubedSum ? std::log1p(sum)
                                                            : options_.product_exponent * sum;
}

double BeamLikelihood::beam_agreement(double log_likelihood, std::size_t beams) const {
  if (beams == 0) return 0.0;
  const double n = static_cast<double>(beams);
  if (options_.combination == BeamCombination::kCubedSum) return std::expm1(log_likelihood) / n;
  return std::exp(log_likelihood / (options_.product_exponent * n));
}

}  // namespace mobot::estimation
