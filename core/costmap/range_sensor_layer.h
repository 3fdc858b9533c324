#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/costmap/costmap_layer.h"
#include "core/geometry/pose2d.h"
#include "core/msgs/sonar_ring.h"
#include "core/planning/planning_grid.h"

namespace mobot::costmap {

struct RangeSensorLayerOptions {
  // One instance per ring: "sonar" or "ir".
  std::string name = "sonar";
  // Readings farther than this are trusted only for clearing (a sonar's far echoes are mostly
  // multipath); 0 or less: trust every reading up to its range_max.
  double max_mark_range_m = 0.0;
  // A reading at range_max (nothing echoed) clears its cone out to range_max. ROS's
  // range_sensor_layer leaves this off because its probabilistic cells forget; these cells do not,
  // so without it a person who walked away from a sonar would stay marked until the window moves.
  bool clear_on_max_reading = true;
  // Radial thickness of the marked arc; 0: one cell's diagonal, so the arc has no holes.
  double arc_thickness_m = 0.0;
  // The heights the ring sees; metadata.
  HeightBand height_band{0.0, 2.0};
};

// Sonar or IR readings as cones (after ROS's range_sensor_layer, without its probabilities): each
// reading clears the cells inside its cone nearer than the echo and marks the arc at the echo's
// range as lethal; a reading at range_max marks nothing. Narrow IR cones may hold no cell centre,
// so the cells along the axis are cleared and the cell at the echo on the axis is marked too. Its
// own grid in master cells like the obstacle layer (kept, shifted, written by max).
class RangeSensorLayer : public CostmapLayer {
 public:
  // Throws std::invalid_argument on non-finite or negative options.
  explicit RangeSensorLayer(const RangeSensorLayerOptions& options = {});

  std::string_view name() const override { return options_.name; }
  HeightBand height_band() const override { return options_.height_band; }
  const RangeSensorLayerOptions& options() const { return options_; }

  // Queues one ring's readings (each with its mounting pose on the base) taken with the base at
  // `base_in_map`. Readings with a NaN range, a range below range_min, a non-positive range_max
  // or a cone outside (0, pi) are skipped. Returns false, queuing nothing, for a non-finite pose.
  bool add_readings(std::span<const msgs::RangeReading> readings,
                    const geometry::Pose2D& base_in_map);
  void clear();
  const planning::PlanningGrid& observed() const { return grid_; }

  void match_geometry(const planning::PlanningGrid& master) override;
  void shift(const planning::PlanningGrid& master, int dx_cells, int dy_cells) override;
  void update_bounds(const planning::PlanningGrid& master, CellBounds& bounds) override;
  void update(planning::PlanningGrid& master, const CellBounds& bounds) override;

 private:
  struct Cone {
    geometry::Pose2D sensor_in_map;
    double half_angle_rad = 0.0;
    double clear_to_m = 0.0;  // the echo's range, or range_max when nothing echoed
    bool echo = false;        // something echoed at clear_to_m: clear short of its arc
    double mark_at_m = -1.0;  // < 0: nothing to mark
  };

  void clear_cone(const Cone& cone, CellBounds& bounds);
  void mark_cone(const Cone& cone, CellBounds& bounds);

  RangeSensorLayerOptions options_;
  planning::PlanningGrid grid_;
  std::vector<Cone> pending_;
  bool cleared_ = false;
};

}  // namespace mobot::costmap
