#include "core/estimation/particle_filter/likelihood_field.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace mobot::estimation {

LikelihoodField::LikelihoodField(const mapping::OccupancyGrid& grid,
                                 const LikelihoodFieldOptions& options)
    : width_(grid.width()),
      height_(grid.height()),
      resolution_m_(grid.resolution_m()),
      origin_(grid.origin()),
      max_distance_m_(options.max_distance_m) {
  if (!(options.max_distance_m > 0.0) || !std::isfinite(options.max_distance_m)) {
    throw std::invalid_argument("likelihood field needs a positive finite max_distance_m");
  }
  const std::size_t count = grid.cells().size();
  distances_m_.assign(count, static_cast<float>(max_distance_m_));
  open_.assign(count, 0);
  if (count == 0) return;
  // distanceTransform measures to the nearest zero pixel: obstacles are the zeros.
  cv::Mat source(height_, width_, CV_8UC1);
  for (int y = 0; y < height_; ++y) {
    auto* row = source.ptr<std::uint8_t>(y);
    for (int x = 0; x < width_; ++x) {
      const bool occupied = grid.is_occupied({x, y});
      has_obstacles_ = has_obstacles_ || occupied;
      row[x] = occupied ? 0 : 1;
      open_[static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
            static_cast<std::size_t>(x)] =
          !occupied && grid.at({x, y}) != mapping::OccupancyGrid::kUnknown ? 1 : 0;
    }
  }
  if (!has_obstacles_) return;
  cv::Mat distance_cells;
  // The exact Euclidean transform (Felzenszwalb-Huttenlocher in OpenCV), not the 3x3 or 5x5 chamfer
  // approximation: the laser model squares these distances.
  cv::distanceTransform(source, distance_cells, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  for (int y = 0; y < height_; ++y) {
    const auto* row = distance_cells.ptr<float>(y);
    for (int x = 0; x < width_; ++x) {
      const double metres = static_cast<double>(row[x]) * resolution_m_;
      distances_m_[static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
                   static_cast<std::size_t>(x)] =
          static_cast<float>(std::min(metres, max_distance_m_));
    }
  }
}

std::optional<std::size_t> LikelihoodField::index_at(geometry::Point2D point_in_map) const {
  if (!std::isfinite(point_in_map.x) || !std::isfinite(point_in_map.y)) return std::nullopt;
  const geometry::Point2D local =
      geometry::transform_point(geometry::inverse(origin_), point_in_map);
  const double cx = std::floor(local.x / resolution_m_);
  const double cy = std::floor(local.y / resolution_m_);
  if (cx < 0.0 || cy < 0.0 || cx >= width_ || cy >= height_) return std::nullopt;
  return static_cast<std::size_t>(cy) * static_cast<std::size_t>(width_) +
         static_cast<std::size_t>(cx);
}

double LikelihoodField::distance_m(geometry::Point2D point_in_map) const {
  const auto index = index_at(point_in_map);
  return index ? static_cast<double>(distances_m_[*index]) : max_distance_m_;
}

bool LikelihoodField::open_at(geometry::Point2D point_in_map) const {
  const auto index = index_at(point_in_map);
  return index && open_[*index] != 0;
}

}  // namespace mobot::estimation
