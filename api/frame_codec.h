#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "api/ports/camera_port.h"
#include "api/ports/control_port.h"
#include "core/estimation/weighted_pose.h"
#include "core/geometry/pose2d.h"
#include "core/mapping/map_tiles.h"
#include "core/mapping/occupancy_grid.h"
#include "core/msgs/image.h"
#include "core/msgs/laser_scan.h"
#include "core/msgs/odometry.h"
#include "core/msgs/sonar_ring.h"
#include "core/perception/point_cloud.h"
#include "core/planning/planning_grid.h"

namespace mobot::api {

// The envelope every stream frame shares; see README "Stream protocol".
struct FrameStamp {
  double t_s = 0.0;
  std::uint64_t seq = 0;
  std::int64_t wall_us = 0;
};

inline constexpr std::size_t kBinaryHeaderBytes = 32;

// `{"topic","t","seq","wall_us","data"}` as text.
std::string encode_json_frame(std::string_view topic, const FrameStamp& stamp,
                              const nlohmann::json& data);

// The camera topic: the body is the JPEG file as the driver encoded it.
std::string encode_binary_camera(const FrameStamp& stamp, const msgs::Image& image);
nlohmann::json camera_json(const msgs::Image& image);
// GET /api/v1/tracking's body and the target topic's data.
nlohmann::json tracking_json(const TrackingSnapshot& snapshot);
std::string encode_binary_scan(const FrameStamp& stamp, const msgs::LaserScan& scan,
                               const geometry::Pose2D& sensor_in_map);
std::string encode_binary_map(const FrameStamp& stamp, const mapping::OccupancyGrid& grid,
                              std::int64_t map_id);

// Where a chunk of a sweep's cloud belongs: README "Cloud body".
struct CloudChunk {
  std::uint32_t sweep_id = 0;
  std::uint32_t first_point = 0;  // index of the chunk's first point within the sweep
  bool last = false;              // the sweep's last chunk
  std::uint32_t scans_done = 0;
  std::uint32_t scans_total = 0;
};

std::string encode_binary_cloud(const FrameStamp& stamp, const CloudChunk& chunk,
                                std::span<const perception::CloudPoint> points);
nlohmann::json cloud_json(const CloudChunk& chunk, std::span<const perception::CloudPoint> points);

nlohmann::json pose_json(const geometry::Pose2D& pose);
nlohmann::json scan_json(const msgs::LaserScan& scan, const geometry::Pose2D& sensor_in_map);
// A ring of range sensors (sonar, IR) with each sensor's pose in the map frame.
nlohmann::json range_ring_json(std::span<const msgs::RangeReading> ring,
                               const geometry::Pose2D& base_in_map);
nlohmann::json map_json(const mapping::OccupancyGrid& grid, std::int64_t map_id);

// The map being built, as changed tiles (README: binary frames, map body with the tiles flag).
std::string encode_binary_map_tiles(const FrameStamp& stamp, const mapping::MapTileUpdate& tiles);
nlohmann::json map_tiles_json(const mapping::MapTileUpdate& tiles);

// A costmap (topics costmap and local_costmap; `local` tells which).
std::string encode_binary_costmap(const FrameStamp& stamp, const planning::PlanningGrid& costmap,
                                  bool local);
nlohmann::json costmap_json(const planning::PlanningGrid& costmap, bool local);

// A sample of the particle filter's belief; `total` is the filter's particle count.
std::string encode_binary_particles(const FrameStamp& stamp,
                                    std::span<const estimation::WeightedPose> particles,
                                    std::size_t total);
nlohmann::json particles_json(std::span<const estimation::WeightedPose> particles,
                              std::size_t total);
nlohmann::json snapshot_json(const RobotSnapshot& snapshot);

}  // namespace mobot::api
