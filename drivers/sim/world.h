#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"

namespace mobot::sim {

// An axis-aligned box in the map frame with a height range: a gate beam, a table top, a cabinet.
struct Box3D {
  double min_x_m = 0.0;
  double min_y_m = 0.0;
  double max_x_m = 0.0;
  double max_y_m = 0.0;
  double min_z_m = 0.0;
  double max_z_m = 0.0;
  std::string name;
  // Furniture drawn on the building's surveyed floor plan (the map the robot is given), though
  // its own 2D laser may not see it; gate beams and the like are not.
  bool on_map = false;
};

// A red cylinder at a known position, used as a bearing landmark (E2 measurement 3).
struct Landmark {
  std::string name;
  double x_m = 0.0;
  double y_m = 0.0;
};

struct World {
  std::string name;
  std::string description;
  geometry::Pose2D start;  // where the robot starts
  // Walls from the floor-plan image: full-height obstacles. This is what the server stores as the
  // world's map.
  mapping::OccupancyGrid floor;
  std::vector<Box3D> boxes;  // 3D objects that the floor plan does not show
  std::vector<Landmark> landmarks;
};

class WorldError : public std::runtime_error {
 public:
  using runtime_error::runtime_error;
};

struct WorldSummary {
  std::string name;
  std::string description;
};

// A built-in name ("office") -> worlds_dir/office/world.yaml; a path to a .yaml file -> itself.
// Throws WorldError when neither exists.
// The map an operator would load for this world: the floor plan's walls plus the boxes marked
// on_map that stand in the robot's height band (they block the robot wherever they are drawn).
mapping::OccupancyGrid surveyed_map(const World& world, double robot_height_m);

std::filesystem::path resolve_world(const std::filesystem::path& worlds_dir,
                                    const std::string& name_or_path);

// Reads a world YAML and its floor-plan image. Throws WorldError naming the file and the key on any
// problem, including keys it does not know. The ROS map_server keys plus the simulator's own:
//   name: office                      # default: the directory's name
//   description: "..."                # optional
//   image: office.pgm                 # PGM or PNG, relative to the YAML file
//   resolution: 0.05                  # metres per pixel
//   origin: [0.0, 0.0, 0.0]           # pose of the image's lower-left corner
//   negate: 0                         # optional, with occupied_thresh (0.65) and free_thresh
//   start: [2.0, 7.5, 0.0]            # optional robot start pose, default (0, 0, 0)
//   boxes:                            # optional: x, y, z of two opposite corners, map frame
//     - {name: table_1, min: [15.0, 11.0, 0.70], max: [16.6, 11.8, 0.75]}
//   landmarks:                        # optional bearing landmarks
//     - {name: lm_corridor_west, x: 0.5, y: 8.2}
World load_world(const std::filesystem::path& world_yaml);

// The worlds found as worlds_dir/NAME/world.yaml, sorted by name (the directory name, which is what
// resolve_world accepts). A missing directory has no worlds.
std::vector<WorldSummary> list_worlds(const std::filesystem::path& worlds_dir);

}  // namespace mobot::sim
