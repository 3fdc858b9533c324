#include "core/estimation/particle_filter/beam_likelihood.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/numeric/finite.h"

namespace mobot::estimation {
namespace {

double hit_term(double distance_m, const BeamLikelihoodOptions& options) {
  return options.z_hit *
         std::exp(-(distance_m * distance_m) / (2.0 * options.sigma_hit_m * options.sigma_hit_m));
}

// Whether the beams within `half_width` of beam i all returned nothing within range_max (a 360
// deg scan wraps round; past the ends of a narrower one there is no telling).
bool open_around(const msgs::LaserScan& scan, int i, int half_width, double range_max) {
  const auto count = static_cast<int>(scan.ranges_m.size());
  const bool full_circle =
      static_cast<double>(count) * std::abs(static_cast<double>(scan.angle_increment_rad)) >=
      2.0 * std::numbers::pi - 1e-3;
  for (int j = i - half_width; j <= i + half_width; ++j) {
    int index = j;
    if (index < 0 || index >= count) {
      if (!full_circle) return false;
      index = (index % count + count) % count;
    }
    const double range = static_cast<double>(scan.ranges_m[static_cast<std::size_t>(index)]);
    if (!(range >= range_max)) return false;  // a return, or NaN
  }
  return true;
}

// Keeps `count` of the points, evenly spread, first and last included.
void thin_evenly(std::vector<geometry::Point2D>& points, std::size_t count) {
  if (points.size() <= count) return;
  std::vector<geometry::Point2D> kept;
  kept.reserve(count);
  const double step =
      count > 1 ? static_cast<double>(points.size() - 1) / static_cast<double>(count - 1) : 0.0;
  for (std::size_t k = 0; k < count; ++k) {
    kept.push_back(points[static_cast<std::size_t>(std::lround(static_cast<double>(k) * step))]);
  }
  points = std::move(kept);
}

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
  if (options.max_beams < 2 || !finite_non_negative(options.z_hit) ||
      !finite_non_negative(options.z_rand) || !finite_positive(options.sigma_hit_m) ||
      !finite_positive(options.range_max_m) || !finite_positive(options.product_exponent) ||
      options.product_exponent > 1.0 || !finite_non_negative(options.no_return_margin_m) ||
      options.max_no_return_beams < 0 || !finite_non_negative(options.no_return_clearance_rad) ||
      !finite_non_negative(options.no_return_weight) || options.no_return_weight > 1.0) {
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
  prepared.sensor_in_base = {scan.sensor_in_base.x, scan.sensor_in_base.y};
  const double free_length_m = range_max - options_.no_return_margin_m;
  const bool free_rays = options_.no_return_beams && free_length_m > range_min;
  const int clearance_beams = static_cast<int>(std::ceil(
      options_.no_return_clearance_rad / std::abs(static_cast<double>(scan.angle_increment_rad)) -
      1e-6));
  for (int k = 0; k < beams; ++k) {
    // Evenly over the whole scan, first and last beam included.
    const int i =
        beams == 1
            ? 0
            : static_cast<int>(std::lround(static_cast<double>(k) * (count - 1) / (beams - 1)));
    const double range = static_cast<double>(scan.ranges_m[static_cast<std::size_t>(i)]);
    if (!(range > range_min)) continue;  // NaN and the too-near readings AMCL also drops
    const bool returned = range < range_max;
    if (!returned && !(free_rays && open_around(scan, i, clearance_beams, range_max))) continue;
    const double bearing =
        static_cast<double>(scan.angle_min_rad) + i * static_cast<double>(scan.angle_increment_rad);
    const double length = returned ? range : free_length_m;
    const double sx = length * std::cos(bearing);
    const double sy = length * std::sin(bearing);
    const geometry::Point2D end{scan.sensor_in_base.x + c * sx - s * sy,
                                scan.sensor_in_base.y + s * sx + c * sy};
    (returned ? prepared.endpoints_in_base : prepared.free_ray_ends_in_base).push_back(end);
  }
  thin_evenly(prepared.free_ray_ends_in_base,
              static_cast<std::size_t>(options_.max_no_return_beams));
  return prepared;
}

double BeamLikelihood::log_likelihood(const PreparedScan& scan,
                                      const geometry::Pose2D& base_in_map) const {
  return log_likelihood(scan, base_in_map, -std::numeric_limits<double>::infinity());
}

double BeamLikelihood::log_likelihood(const PreparedScan& scan, const geometry::Pose2D& base_in_map,
                                      double negligible_below) const {
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
  if (!scan.free_ray_ends_in_base.empty()) {
    const double clear = options_.no_return_weight * beam_term(options_.z_hit, scan.rand_term);
    const double blocked = options_.no_return_weight * beam_term(0.0, scan.rand_term);
    const double rays = static_cast<double>(scan.free_ray_ends_in_base.size());
    if (options_.combination == BeamCombination::kProduct &&
        options_.product_exponent * (sum + rays * clear) < negligible_below) {
      return options_.product_exponent * (sum + rays * blocked);
    }
    const double sx =
        (base.x + c * scan.sensor_in_base.x - s * scan.sensor_in_base.y) * inverse_resolution;
    const double sy =
        (base.y + s * scan.sensor_in_base.x + c * scan.sensor_in_base.y) * inverse_resolution;
    std::array<RayWalk, kRaysWalkedTogether> walks;
    std::size_t pending = 0;
    std::size_t blocked_rays = 0;
    for (const geometry::Point2D& end : scan.free_ray_ends_in_base) {
      const double ex = (base.x + c * end.x - s * end.y) * inverse_resolution;
      const double ey = (base.y + s * end.x + c * end.y) * inverse_resolution;
      if (start_walk(sx, sy, ex, ey, walks[pending])) ++pending;
      if (pending == walks.size()) {
        blocked_rays += count_blocked({walks.data(), pending});
        pending = 0;
      }
    }
    blocked_rays += count_blocked({walks.data(), pending});
    sum += static_cast<double>(blocked_rays) * blocked +
           (rays - static_cast<double>(blocked_rays)) * clear;
  }
  return options_.combination == BeamCombination::kCubedSum ? std::log1p(sum)
                                                            : options_.product_exponent * sum;
}

bool BeamLikelihood::segment_free(geometry::Point2D from_in_map,
                                  geometry::Point2D to_in_map) const {
  const geometry::Point2D from = geometry::transform_point(grid_from_map_, from_in_map);
  const geometry::Point2D to = geometry::transform_point(grid_from_map_, to_in_map);
  const double inverse_resolution = 1.0 / field_->resolution_m();
  return segment_free_cells(from.x * inverse_resolution, from.y * inverse_resolution,
                            to.x * inverse_resolution, to.y * inverse_resolution);
}

bool BeamLikelihood::segment_free_cells(double x0, double y0, double x1, double y1) const {
  RayWalk walk;
  return !start_walk(x0, y0, x1, y1, walk) || count_blocked({&walk, 1}) == 0;
}

bool BeamLikelihood::start_walk(double x0, double y0, double x1, double y1, RayWalk& walk) {
  if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1)) {
    return false;
  }
  // Not std::hypot: it costs as much as the rest of a short walk.
  const double length = std::sqrt((x1 - x0) * (x1 - x0) + (y1 - y0) * (y1 - y0));
  if (!(length > 0.0)) return false;
  walk = {x0, y0, (x1 - x0) / length, (y1 - y0) / length, length, 0.0};
  return true;
}

std::size_t BeamLikelihood::count_blocked(std::span<RayWalk> walks) const {
  const int width = field_->width();
  const int height = field_->height();
  const float* distances = field_->distances_m().data();
  const double inverse_resolution = 1.0 / field_->resolution_m();
  // A step of the distance to the nearest occupied cell less a cell cannot pass one (up to the
  // corner of a cell). Near a wall the walk goes by two cells and stops in any cell next to an
  // occupied one: a wall and its two neighbours are three cells across, so no step of two cells
  // jumps it, whatever the angle. A ray grazing a wall within a cell counts as blocked.
  constexpr double kMinStepCells = 2.0;
  constexpr double kSafetyCells = 1.0;
  // Next to an occupied cell: 1 cell across, 1.41 diagonally (and the field's float metres).
  constexpr double kBlockedWithinCells = 1.5;
  // The rays advance a step each in turn: every step waits on a look-up that depends on the
  // last, and the walks of different rays overlap those waits.
  std::size_t active = walks.size();
  std::size_t blocked = 0;
  while (active > 0) {
    for (std::size_t k = 0; k < active;) {
      RayWalk& walk = walks[k];
      const double x = walk.x0 + walk.ux * walk.t;
      const double y = walk.y0 + walk.uy * walk.t;
      // Past its end, or off the grid (a rectangle: a ray that leaves it does not come back).
      bool finished = walk.t > walk.length || x < 0.0 || y < 0.0 || x >= width || y >= height;
      if (!finished) {
        const auto cell =
            static_cast<std::size_t>(static_cast<int>(y)) * static_cast<std::size_t>(width) +
            static_cast<std::size_t>(static_cast<int>(x));
        const double distance_cells = static_cast<double>(distances[cell]) * inverse_resolution;
        if (distance_cells < kBlockedWithinCells) {
          ++blocked;
          finished = true;
        } else {
          walk.t += std::max(distance_cells - kSafetyCells, kMinStepCells);
        }
      }
      if (finished) {
        walk = walks[--active];
      } else {
        ++k;
      }
    }
  }
  return blocked;
}

double BeamLikelihood::beam_agreement(double log_likelihood, std::size_t beams) const {
  if (beams == 0) return 0.0;
  const double n = static_cast<double>(beams);
  if (options_.combination == BeamCombination::kCubedSum) return std::expm1(log_likelihood) / n;
  return std::exp(log_likelihood / (options_.product_exponent * n));
}

}  // namespace mobot::estimation
