#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/costmap/costmap_layer.h"
#include "core/geometry/pose2d.h"
#include "core/geometry/simple_polygon.h"
#include "core/planning/planning_grid.h"

namespace mobot::costmap {

struct KeepoutLayerOptions {
  std::string name = "keepout";
  // At most this many zones (each a simple polygon of up to 256 vertices).
  std::size_t max_zones = 64;
};

// Keep-out zones (Nav2's keepout filter): simple polygons in the map frame rasterised as lethal.
// A master cell is marked when its centre lies inside a zone or a zone's edge crosses it, so a
// zone thinner than a cell still blocks. Rasterised into its own grid in master cells; written by
// max.
class KeepoutLayer : public CostmapLayer {
 public:
  explicit KeepoutLayer(const KeepoutLayerOptions& options = {});

  std::string_view name() const override { return options_.name; }

  // Replaces every zone. Returns why the zones were refused ("zone 2: vertex 1 is not finite"),
  // keeping the previous ones, or nullopt when they were accepted.
  std::optional<std::string> set_zones(const std::vector<std::vector<geometry::Point2D>>& zones);
  const std::vector<geometry::SimplePolygon>& zones() const { return zones_; }

  void match_geometry(const planning::PlanningGrid& master) override;
  void shift(const planning::PlanningGrid& master, int dx_cells, int dy_cells) override;
  void update_bounds(const planning::PlanningGrid& master, CellBounds& bounds) override;
  void update(planning::PlanningGrid& master, const CellBounds& bounds) override;

 private:
  void rasterise(const CellBounds& bounds);

  KeepoutLayerOptions options_;
  std::vector<geometry::SimplePolygon> zones_;
  planning::PlanningGrid grid_;
  bool changed_ = false;
};

}  // namespace mobot::costmap
