#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>

#include "core/perception/obstacle_layer_3d.h"
#include "server/map_listener.h"

namespace mobot::server {

// The 3D-obstacle layer over the active map, shared by the sweeps' processing (which merges each
// IPaBD result) and map activation (which starts it afresh for a new map). Thread-safe.
class SweepLayer final : public MapListener {
 public:
  // `cell_m`: IPaBD's cell, a third of the robot's width (docs/algorithms.md P2).
  explicit SweepLayer(double cell_m) : cell_m_(cell_m) {}

  void prepare_map(const ActiveMap& map) override;
  void apply_map(const ActiveMap&, TickContext&) override {}

  // The layer's cell corners, for IPaBD to compute on the same lattice.
  geometry::Point2D lattice_origin() const;
  // Merges an (undilated) IPaBD result measured on map `generation`; the layer as it is now, or
  // nothing when the active map has changed since and the result was dropped.
  std::optional<std::shared_ptr<const mapping::OccupancyGrid>> merge(
      const mapping::OccupancyGrid& observed, std::uint64_t generation);

 private:
  const double cell_m_;
  mutable std::mutex mutex_;
  perception::ObstacleLayer3D layer_;
  std::uint64_t generation_ = 0;
};

}  // namespace mobot::server
