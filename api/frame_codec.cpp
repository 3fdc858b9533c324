#include "api/frame_codec.h"

#include <openssl/evp.h>

#include <bit>
#include <cstring>

#include "api/stream_topics.h"

namespace mobot::api {
namespace {

// Little-endian appenders; the host is little-endian (x86-64, arm64), checked at compile time.
static_assert(std::endian::native == std::endian::little, "binary frames are little-endian");

template <class T>
void append(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

void append_header(std::string& out, std::uint16_t topic_binary_id, const FrameStamp& stamp) {
  out.append("MBT1", 4);
  append<std::uint16_t>(out, topic_binary_id);
  append<std::uint16_t>(out, static_cast<std::uint16_t>(kBinaryHeaderBytes));
  append<std::uint64_t>(out, stamp.seq);
  append<double>(out, stamp.t_s);
  append<std::int64_t>(out, stamp.wall_us);
}

}  // namespace

std::string encode_json_frame(std::string_view topic, const FrameStamp& stamp,
                              const nlohmann::json& data) {
  std::string out = R"({"topic":")";
  out.append(topic);
  out.append(R"(","t":)");
  out.append(nlohmann::json(stamp.t_s).dump());
  out.append(R"(,"seq":)");
  out.append(std::to_string(stamp.seq));
  out.append(R"(,"wall_us":)");
  out.append(std::to_string(stamp.wall_us));
  out.append(R"(,"data":)");
  out.append(data.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  out.push_back('}');
  return out;
}

std::string encode_binary_scan(const FrameStamp& stamp, const msgs::LaserScan& scan,
                               const geometry::Pose2D& sensor_in_map) {
  std::string out;
  out.reserve(kBinaryHeaderBytes + 32 + scan.ranges_m.size() * sizeof(float));
  append_header(out, topic_spec(TopicId::kScan).binary_id, stamp);
  append<float>(out, scan.angle_min_rad);
  append<float>(out, scan.angle_increment_rad);
  append<float>(out, scan.range_min_m);
  append<float>(out, scan.range_max_m);
  append<float>(out, static_cast<float>(sensor_in_map.x));
  append<float>(out, static_cast<float>(sensor_in_map.y));
  append<float>(out, static_cast<float>(sensor_in_map.theta));
  append<std::uint32_t>(out, static_cast<std::uint32_t>(scan.ranges_m.size()));
  out.append(reinterpret_cast<const char*>(scan.ranges_m.data()),
             scan.ranges_m.size() * sizeof(float));
  return out;
}

std::string encode_binary_camera(const FrameStamp& stamp, const msgs::Image& image) {
  std::string out;
  out.reserve(kBinaryHeaderBytes + image.data.size());
  append_header(out, topic_spec(TopicId::kCamera).binary_id, stamp);
  out.append(reinterpret_cast<const char*>(image.data.data()), image.data.size());
  return out;
}

nlohmann::json camera_json(const msgs::Image& image) {
  // JSON clients get the frame as base64 (a third larger); the dashboard takes the binary one.
  std::string base64(4 * ((image.data.size() + 2) / 3) + 1, '\0');
  const int length = EVP_EncodeBlock(reinterpret_cast<unsigned char*>(base64.data()),
                                     image.data.data(), static_cast<int>(image.data.size()));
  base64.resize(static_cast<std::size_t>(std::max(length, 0)));
  return {{"width", image.width},
          {"height", image.height},
          {"encoding", image.encoding},
          {"data_base64", std::move(base64)}};
}

std::string encode_binary_map(const FrameStamp& stamp, const mapping::OccupancyGrid& grid,
                              std::int64_t map_id) {
  std::string out;
  out.reserve(kBinaryHeaderBytes + 32 + grid.cells().size());
  append_header(out, topic_spec(TopicId::kMap).binary_id, stamp);
  append<std::uint32_t>(out, static_cast<std::uint32_t>(grid.width()));
  append<std::uint32_t>(out, static_cast<std::uint32_t>(grid.height()));
  append<float>(out, static_cast<float>(grid.resolution_m()));
  append<float>(out, static_cast<float>(grid.origin().x));
  append<float>(out, static_cast<float>(grid.origin().y));
  append<float>(out, static_cast<float>(grid.origin().theta));
  append<std::uint32_t>(out, static_cast<std::uint32_t>(map_id));
  append<std::uint32_t>(out, 0);
  out.append(reinterpret_cast<const char*>(grid.cells().data()), grid.cells().size());
  return out;
}

std::string encode_binary_map_tiles(const FrameStamp& stamp, const mapping::MapTileUpdate& tiles) {
  const auto cells = static_cast<std::size_t>(tiles.tile_cells) * tiles.tile_cells;
  std::string out;
  out.reserve(kBinaryHeaderBytes + 32 + tiles.tiles.size() * (8 + cells + 3));
  append_header(out, topic_spec(TopicId::kMap).binary_id, stamp);
  append<std::uint32_t>(out, static_cast<std::uint32_t>(tiles.tile_cells));
  append<std::uint32_t>(out, static_cast<std::uint32_t>(tiles.tiles.size()));
  append<float>(out, static_cast<float>(tiles.resolution_m));
  append<float>(out, static_cast<float>(tiles.lattice_origin.x));
  append<float>(out, static_cast<float>(tiles.lattice_origin.y));
  append<float>(out, static_cast<float>(tiles.lattice_origin.theta));
  append<std::uint32_t>(out, 0);  // the map being built has no id yet
  append<std::uint32_t>(out, kMapFlagTiles);
  for (const auto& tile : tiles.tiles) {
    append<std::int32_t>(out, tile.x);
    append<std::int32_t>(out, tile.y);
    out.append(reinterpret_cast<const char*>(tile.cells.data()), tile.cells.size());
    // Every offset stays a multiple of 4 (an odd tile size would break Float32Array views).
    out.append((4 - tile.cells.size() % 4) % 4, '\0');
  }
  return out;
}

nlohmann::json map_tiles_json(const mapping::MapTileUpdate& tiles) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& tile : tiles.tiles) {
    std::vector<int> data;
    data.reserve(tile.cells.size());
    for (const std::uint8_t cell : tile.cells) {
      data.push_back(cell == mapping::OccupancyGrid::kUnknown ? -1 : cell);
    }
    list.push_back({{"x", tile.x}, {"y", tile.y}, {"data", std::move(data)}});
  }
  return {{"tiles", std::move(list)},
          {"id", 0},
          {"tile_cells", tiles.tile_cells},
          {"resolution", tiles.resolution_m},
          {"origin", pose_json(tiles.lattice_origin)}};
}

std::string encode_binary_costmap(const FrameStamp& stamp, const planning::PlanningGrid& costmap,
                                  bool local) {
  std::string out;
  out.reserve(kBinaryHeaderBytes + 32 + costmap.costs().size() + 3);
  append_header(out, topic_spec(TopicId::kCostmap).binary_id, stamp);
  append<std::uint32_t>(out, static_cast<std::uint32_t>(costmap.width()));
  append<std::uint32_t>(out, static_cast<std::uint32_t>(costmap.height()));
  append<float>(out, static_cast<float>(costmap.resolution_m()));
  append<float>(out, static_cast<float>(costmap.origin().x));
  append<float>(out, static_cast<float>(costmap.origin().y));
  append<float>(out, static_cast<float>(costmap.origin().theta));
  append<std::uint32_t>(out, local ? 1U : 0U);
  append<std::uint32_t>(out, 0);
  out.append(reinterpret_cast<const char*>(costmap.costs().data()), costmap.costs().size());
  return out;
}

nlohmann::json costmap_json(const planning::PlanningGrid& costmap, bool local) {
  return {{"which", local ? "local" : "global"},
          {"width", costmap.width()},
          {"height", costmap.height()},
          {"resolution", costmap.resolution_m()},
          {"origin", pose_json(costmap.origin())},
          {"data", costmap.costs()}};
}

std::string encode_binary_particles(const FrameStamp& stamp,
                                    std::span<const estimation::WeightedPose> particles,
                                    std::size_t total) {
  std::string out;
  out.reserve(kBinaryHeaderBytes + 32 + particles.size() * 16);
  append_header(out, topic_spec(TopicId::kParticles).binary_id, stamp);
  append<std::uint32_t>(out, static_cast<std::uint32_t>(particles.size()));
  append<std::uint32_t>(out, static_cast<std::uint32_t>(total));
  for (int i = 0; i < 6; ++i) append<std::uint32_t>(out, 0);
  for (const auto& particle : particles) {
    append<float>(out, static_cast<float>(particle.pose.x));
    append<float>(out, static_cast<float>(particle.pose.y));
    append<float>(out, static_cast<float>(particle.pose.theta));
    append<float>(out, static_cast<float>(particle.weight));
  }
  return out;
}

nlohmann::json particles_json(std::span<const estimation::WeightedPose> particles,
                              std::size_t total) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& p : particles) list.push_back({p.pose.x, p.pose.y, p.pose.theta, p.weight});
  return {{"count", particles.size()}, {"total", total}, {"particles", std::move(list)}};
}

std::string encode_binary_cloud(const FrameStamp& stamp, const CloudChunk& chunk,
                                std::span<const perception::CloudPoint> points) {
  static_assert(sizeof(perception::CloudPoint) == 16, "x, y, z, intensity as four float32");
  std::string out;
  out.reserve(kBinaryHeaderBytes + 32 + points.size() * sizeof(perception::CloudPoint));
  append_header(out, topic_spec(TopicId::kCloud).binary_id, stamp);
  append<std::uint32_t>(out, chunk.sweep_id);
  append<std::uint32_t>(out, chunk.first_point);
  append<std::uint32_t>(out, static_cast<std::uint32_t>(points.size()));
  append<std::uint32_t>(out, chunk.last ? 1U : 0U);
  append<std::uint32_t>(out, chunk.scans_done);
  append<std::uint32_t>(out, chunk.scans_total);
  append<std::uint32_t>(out, 0);
  append<std::uint32_t>(out, 0);
  out.append(reinterpret_cast<const char*>(points.data()),
             points.size() * sizeof(perception::CloudPoint));
  return out;
}

nlohmann::json cloud_json(const CloudChunk& chunk, std::span<const perception::CloudPoint> points) {
  nlohmann::json xyzi = nlohmann::json::array();
  for (const auto& p : points) xyzi.push_back({p.x_m, p.y_m, p.z_m, p.intensity});
  return {{"sweep_id", chunk.sweep_id},     {"first", chunk.first_point},
          {"count", points.size()},         {"last", chunk.last},
          {"scans_done", chunk.scans_done}, {"scans_total", chunk.scans_total},
          {"points", std::move(xyzi)}};
}

nlohmann::json pose_json(const geometry::Pose2D& pose) {
  return {{"x", pose.x}, {"y", pose.y}, {"theta", pose.theta}};
}

nlohmann::json scan_json(const msgs::LaserScan& scan, const geometry::Pose2D& sensor_in_map) {
  return {{"angle_min", scan.angle_min_rad}, {"angle_increment", scan.angle_increment_rad},
          {"range_min", scan.range_min_m},   {"range_max", scan.range_max_m},
          {"ranges", scan.ranges_m},         {"sensor_pose", pose_json(sensor_in_map)}};
}

nlohmann::json range_ring_json(std::span<const msgs::RangeReading> ring,
                               const geometry::Pose2D& base_in_map) {
  nlohmann::json readings = nlohmann::json::array();
  for (const auto& reading : ring) {
    const geometry::Pose2D sensor = geometry::compose(base_in_map, reading.sensor_in_base);
    readings.push_back({{"x", sensor.x},
                        {"y", sensor.y},
                        {"theta", sensor.theta},
                        {"cone", reading.cone_rad},
                        {"range", reading.range_m},
                        {"range_min", reading.range_min_m},
                        {"range_max", reading.range_max_m}});
  }
  return {{"readings", std::move(readings)}};
}

nlohmann::json map_json(const mapping::OccupancyGrid& grid, std::int64_t map_id) {
  std::vector<int> data;
  data.reserve(grid.cells().size());
  for (const std::uint8_t cell : grid.cells()) {
    data.push_back(cell == mapping::OccupancyGrid::kUnknown ? -1 : cell);
  }
  return {{"id", map_id},
          {"width", grid.width()},
          {"height", grid.height()},
          {"resolution", grid.resolution_m()},
          {"origin", pose_json(grid.origin())},
          {"data", std::move(data)}};
}

nlohmann::json snapshot_json(const RobotSnapshot& snapshot) {
  nlohmann::json sensors = nlohmann::json::object();
  for (const auto& [name, health] : snapshot.sensors) {
    sensors[name] = {{"ok", health.ok}, {"rate_hz", health.rate_hz}};
    // Why not: "stale" (silent past its time-out) or the driver's word ("missing", "silent",
    // "checksum", "garbage", ...).
    if (!health.ok) sensors[name]["reason"] = health.reason;
  }
  nlohmann::json body{
      {"t", snapshot.t_s},
      {"mode", snapshot.mode},
      {"pose", pose_json(snapshot.pose)},
      {"velocity", {{"v", snapshot.velocity.linear_mps}, {"w", snapshot.velocity.angular_radps}}},
      {"localization",
       {{"method", snapshot.localization_method},
        {"cov", snapshot.covariance},
        {"converged", snapshot.localization_converged}}},
      {"kinematics", snapshot.kinematics},
      {"estop", snapshot.estop},
      {"sensors", std::move(sensors)},
      {"geometry",
       {{"footprint_length_m", snapshot.geometry.footprint_length_m},
        {"footprint_width_m", snapshot.geometry.footprint_width_m},
        {"footprint_offset_m", snapshot.geometry.footprint_offset_m},
        {"wheelbase_m", snapshot.geometry.wheelbase_m}}}};
  if (snapshot.steering_rad) body["steering_rad"] = *snapshot.steering_rad;
  return body;
}

nlohmann::json tracking_json(const TrackingSnapshot& snapshot) {
  nlohmann::json body{{"status", snapshot.status}};
  if (snapshot.box) {
    body["box"] = {{"x", snapshot.box->x}, {"y", snapshot.box->y}, {"w", snapshot.box->w},
                   {"h", snapshot.box->h}};
  }
  if (snapshot.target) body["target"] = {{"x", snapshot.target->x}, {"y", snapshot.target->y}};
  if (snapshot.range_m) body["range_m"] = *snapshot.range_m;
  return body;
}

}  // namespace mobot::api
