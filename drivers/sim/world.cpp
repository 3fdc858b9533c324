#include "drivers/sim/world.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <optional>
#include <set>
#include <string_view>

#include "core/mapping/map_image_codec.h"

namespace mobot::sim {
namespace {

namespace fs = std::filesystem;

constexpr std::array<std::string_view, 12> kTopLevelKeys = {
    "name",        "description", "image", "resolution", "origin",   "negate", "occupied_thresh",
    "free_thresh", "mode",        "start", "boxes",      "landmarks"};
constexpr std::array<std::string_view, 4> kBoxKeys = {"name", "min", "max", "on_map"};
constexpr std::array<std::string_view, 3> kLandmarkKeys = {"name", "x", "y"};

// Reads one world file; every error names the file and the key it is about.
class WorldFileReader {
 public:
  explicit WorldFileReader(fs::path file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& problem) const {
    throw WorldError("world file '" + file_.string() + "': key '" + key + "' " + problem);
  }
  [[noreturn]] void fail_file(const std::string& problem) const {
    throw WorldError("world file '" + file_.string() + "': " + problem);
  }

  YAML::Node parse() const {
    if (!fs::is_regular_file(file_)) fail_file("does not exist");
    YAML::Node root;
    try {
      root = YAML::LoadFile(file_.string());
    } catch (const YAML::Exception& error) {
      fail_file(std::string("is not valid YAML: ") + error.what());
    }
    if (!root.IsMap()) fail_file("must hold a YAML mapping");
    return root;
  }

  template <std::size_t N>
  void reject_unknown_keys(const YAML::Node& map, const std::array<std::string_view, N>& known,
                           const std::string& prefix) const {
    for (const auto& entry : map) {
      if (!entry.first.IsScalar()) fail(prefix + "?", "keys must be plain strings");
      const std::string key = entry.first.as<std::string>();
      if (std::find(known.begin(), known.end(), key) == known.end()) {
        fail(prefix + key, "is not a known key");
      }
    }
  }

  double number(const YAML::Node& node, const std::string& key) const {
    if (!node.IsDefined() || node.IsNull()) fail(key, "is missing");
    if (!node.IsScalar()) fail(key, "must be a number");
    double value = 0.0;
    try {
      value = node.as<double>();
    } catch (const YAML::Exception&) {
      fail(key, "must be a number");
    }
    if (!std::isfinite(value)) fail(key, "must be finite");
    return value;
  }

  double number_or(const YAML::Node& map, const std::string& key, double fallback) const {
    const YAML::Node node = map[key];  // const operator[] never inserts
    return node.IsDefined() ? number(node, key) : fallback;
  }

  std::vector<double> numbers(const YAML::Node& node, const std::string& key,
                              std::size_t count) const {
    if (!node.IsDefined() || node.IsNull()) fail(key, "is missing");
    if (!node.IsSequence() || node.size() != count) {
      fail(key, "must be a list of " + std::to_string(count) + " numbers");
    }
    std::vector<double> values;
    for (std::size_t i = 0; i < count; ++i) {
      values.push_back(number(node[i], key + "[" + std::to_string(i) + "]"));
    }
    return values;
  }

  std::string text(const YAML::Node& node, const std::string& key) const {
    if (!node.IsDefined() || node.IsNull()) fail(key, "is missing");
    if (!node.IsScalar()) fail(key, "must be a string");
    return node.as<std::string>();
  }

  std::string text_or(const YAML::Node& map, const std::string& key,
                      const std::string& fallback) const {
    const YAML::Node node = map[key];  // const operator[] never inserts
    return node.IsDefined() ? text(node, key) : fallback;
  }

  // map_server writes negate as 0/1; accept YAML booleans too.
  bool flag_or(const YAML::Node& map, const std::string& key, bool fallback) const {
    const YAML::Node node = map[key];  // const operator[] never inserts
    if (!node.IsDefined()) return fallback;
    if (!node.IsScalar()) fail(key, "must be 0, 1, true or false");
    const std::string value = node.as<std::string>();
    if (value == "0" || value == "false") return false;
    if (value == "1" || value == "true") return true;
    fail(key, "must be 0, 1, true or false");
  }

  geometry::Pose2D pose(const YAML::Node& node, const std::string& key) const {
    const std::vector<double> values = numbers(node, key, 3);
    return {values[0], values[1], values[2]};
  }

  const fs::path& file() const { return file_; }

 private:
  fs::path file_;
};

// One world's floor plan: 8000 x 8000 cells is 400 x 400 m at 0.05 m.
constexpr std::size_t kMaxFloorCells = 64'000'000;

std::vector<std::uint8_t> read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

mapping::MapImageOptions read_image_options(const WorldFileReader& reader, const YAML::Node& root) {
  mapping::MapImageOptions options;
  options.negate = reader.flag_or(root, "negate", false);
  options.occupied_thresh = reader.number_or(root, "occupied_thresh", options.occupied_thresh);
  options.free_thresh = reader.number_or(root, "free_thresh", options.free_thresh);
  if (options.occupied_thresh < 0.0 || options.occupied_thresh > 1.0) {
    reader.fail("occupied_thresh", "must lie in [0, 1]");
  }
  if (options.free_thresh < 0.0 || options.free_thresh > options.occupied_thresh) {
    reader.fail("free_thresh", "must lie in [0, occupied_thresh]");
  }
  const std::string mode = reader.text_or(root, "mode", "trinary");
  if (mode != "trinary") reader.fail("mode", "must be 'trinary' (got '" + mode + "')");
  return options;
}

// The floor plan with ROS map_server semantics (core/mapping/map_image_codec).
mapping::OccupancyGrid read_floor(const WorldFileReader& reader, const YAML::Node& root) {
  const double resolution_m = reader.number(root["resolution"], "resolution");
  if (resolution_m <= 0.0) reader.fail("resolution", "must be positive");
  const geometry::Pose2D origin = reader.pose(root["origin"], "origin");
  const mapping::MapImageOptions options = read_image_options(reader, root);
  const fs::path image_name = reader.text(root["image"], "image");
  const fs::path image_path =
      image_name.is_absolute() ? image_name : reader.file().parent_path() / image_name;
  if (!fs::is_regular_file(image_path)) {
    reader.fail("image", "names '" + image_path.string() + "', which does not exist");
  }
  try {
    return mapping::decode_map_image(read_bytes(image_path), resolution_m, origin, options,
                                     kMaxFloorCells);
  } catch (const mapping::MapImageError& error) {
    reader.fail("image", "names '" + image_path.string() + "': " + error.what());
  }
}

Box3D read_box(const WorldFileReader& reader, const YAML::Node& node, const std::string& key) {
  if (!node.IsMap()) reader.fail(key, "must be a mapping with name, min and max");
  reader.reject_unknown_keys(node, kBoxKeys, key + ".");
  const std::vector<double> lo = reader.numbers(node["min"], key + ".min", 3);
  const std::vector<double> hi = reader.numbers(node["max"], key + ".max", 3);
  for (std::size_t axis = 0; axis < 3; ++axis) {
    if (!(lo[axis] < hi[axis])) reader.fail(key, "needs min < max on every axis");
  }
  Box3D box{lo[0], lo[1], hi[0], hi[1], lo[2], hi[2], reader.text(node["name"], key + ".name")};
  if (box.name.empty()) reader.fail(key + ".name", "must not be empty");
  if (const YAML::Node on_map = node["on_map"]; on_map.IsDefined()) {
    try {
      box.on_map = on_map.as<bool>();
    } catch (const YAML::Exception&) {
      reader.fail(key + ".on_map", "must be true or false");
    }
  }
  return box;
}

std::vector<Box3D> read_boxes(const WorldFileReader& reader, const YAML::Node& root) {
  const YAML::Node list = root["boxes"];
  std::vector<Box3D> boxes;
  if (!list.IsDefined() || list.IsNull()) return boxes;
  if (!list.IsSequence()) reader.fail("boxes", "must be a list");
  std::set<std::string> names;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string key = "boxes[" + std::to_string(i) + "]";
    boxes.push_back(read_box(reader, list[i], key));
    // Collisions are reported by box name, so two boxes must not share one.
    if (!names.insert(boxes.back().name).second) {
      reader.fail(key + ".name", "repeats '" + boxes.back().name + "'");
    }
  }
  return boxes;
}

std::vector<Landmark> read_landmarks(const WorldFileReader& reader, const YAML::Node& root) {
  const YAML::Node list = root["landmarks"];
  std::vector<Landmark> landmarks;
  if (!list.IsDefined() || list.IsNull()) return landmarks;
  if (!list.IsSequence()) reader.fail("landmarks", "must be a list");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string key = "landmarks[" + std::to_string(i) + "]";
    const YAML::Node node = list[i];
    if (!node.IsMap()) reader.fail(key, "must be a mapping with name, x and y");
    reader.reject_unknown_keys(node, kLandmarkKeys, key + ".");
    landmarks.push_back({reader.text(node["name"], key + ".name"),
                         reader.number(node["x"], key + ".x"),
                         reader.number(node["y"], key + ".y")});
  }
  return landmarks;
}

void check_start_on_map(const WorldFileReader& reader, const World& world) {
  if (!world.floor.cell_at({world.start.x, world.start.y}).has_value()) {
    reader.fail("start", "lies outside the floor plan");
  }
}

std::string joined_names(const std::vector<WorldSummary>& worlds) {
  if (worlds.empty()) return "(none)";
  std::string out;
  for (const auto& world : worlds) {
    if (!out.empty()) out += ", ";
    out += world.name;
  }
  return out;
}

bool looks_like_path(const std::string& name_or_path) {
  const fs::path path(name_or_path);
  return name_or_path.find('/') != std::string::npos || path.extension() == ".yaml" ||
         path.extension() == ".yml";
}

}  // namespace

std::filesystem::path resolve_world(const std::filesystem::path& worlds_dir,
                                    const std::string& name_or_path) {
  if (looks_like_path(name_or_path)) {
    fs::path path(name_or_path);
    if (fs::is_regular_file(path)) return path;
    if (fs::is_directory(path) && fs::is_regular_file(path / "world.yaml")) {
      return path / "world.yaml";
    }
  } else if (!name_or_path.empty() && name_or_path != "." && name_or_path != "..") {
    fs::path candidate = worlds_dir / name_or_path / "world.yaml";
    if (fs::is_regular_file(candidate)) return candidate;
  }
  throw WorldError("unknown world '" + name_or_path + "': built-in worlds are " +
                   joined_names(list_worlds(worlds_dir)));
}

World load_world(const std::filesystem::path& world_yaml) {
  const WorldFileReader reader(world_yaml);
  const YAML::Node root = reader.parse();
  reader.reject_unknown_keys(root, kTopLevelKeys, "");
  World world;
  world.name = reader.text_or(root, "name", world_yaml.parent_path().filename().string());
  world.description = reader.text_or(root, "description", "");
  world.floor = read_floor(reader, root);
  world.start =
      root["start"].IsDefined() ? reader.pose(root["start"], "start") : geometry::Pose2D{};
  world.start.theta = geometry::wrap_angle(world.start.theta);
  check_start_on_map(reader, world);
  world.boxes = read_boxes(reader, root);
  world.landmarks = read_landmarks(reader, root);
  return world;
}

std::vector<WorldSummary> list_worlds(const std::filesystem::path& worlds_dir) {
  std::vector<WorldSummary> worlds;
  std::error_code error;
  if (!fs::is_directory(worlds_dir, error)) return worlds;
  for (const auto& entry : fs::directory_iterator(worlds_dir, error)) {
    const fs::path yaml = entry.path() / "world.yaml";
    if (!entry.is_directory() || !fs::is_regular_file(yaml)) continue;
    const WorldFileReader reader(yaml);
    const YAML::Node root = reader.parse();
    worlds.push_back({entry.path().filename().string(), reader.text_or(root, "description", "")});
  }
  std::sort(worlds.begin(), worlds.end(),
            [](const WorldSummary& a, const WorldSummary& b) { return a.name < b.name; });
  return worlds;
}

mapping::OccupancyGrid surveyed_map(const World& world, double robot_height_m) {
  mapping::OccupancyGrid map = world.floor;
  for (const Box3D& box : world.boxes) {
    if (!box.on_map || box.min_z_m >= robot_height_m || box.max_z_m <= 0.0) continue;
    const mapping::CellIndex lo = map.cell_at_unchecked({box.min_x_m, box.min_y_m});
    const mapping::CellIndex hi = map.cell_at_unchecked({box.max_x_m, box.max_y_m});
    for (int y = std::max(lo.y, 0); y <= std::min(hi.y, map.height() - 1); ++y) {
      for (int x = std::max(lo.x, 0); x <= std::min(hi.x, map.width() - 1); ++x) {
        map.set({x, y}, mapping::OccupancyGrid::kOccupied);
      }
    }
  }
  return map;
}

}  // namespace mobot::sim
