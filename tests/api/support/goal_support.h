#pragma once

// Helpers for the goal-navigation API tests: the active map as a grid (from map.pgm), clearance
// queries on it, waits for a goal to end on the robot clock, angle and pose arithmetic.

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "support/api_test.h"

namespace mobot::testing {

inline double wrap_angle(double angle) {
  angle = std::fmod(angle + std::numbers::pi, 2.0 * std::numbers::pi);
  if (angle < 0.0) angle += 2.0 * std::numbers::pi;
  return angle - std::numbers::pi;
}

inline double xy_distance(const json& a, const json& b) {
  return std::hypot(a.at("x").get<double>() - b.at("x").get<double>(),
                    a.at("y").get<double>() - b.at("y").get<double>());
}

inline double heading_error(const json& a, const json& b) {
  return std::abs(wrap_angle(a.at("theta").get<double>() - b.at("theta").get<double>()));
}

inline std::string pose_text(const json& pose) {
  std::ostringstream out;
  out.precision(3);
  out << std::fixed << "(" << pose.value("x", std::nan("")) << ", "
      << pose.value("y", std::nan(""));
  if (pose.contains("theta")) out << ", " << pose.at("theta").get<double>();
  out << ")";
  return out.str();
}

// The id of the active map, or -1.
inline std::int64_t active_map_id(const HttpClient& client) {
  const HttpReply reply = client.get("/api/v1/maps");
  EXPECT_EQ(reply.status, 200) << reply.body;
  if (reply.status != 200) return -1;
  for (const auto& map : reply.json()) {
    if (map.value("active", false)) return map.at("id").get<std::int64_t>();
  }
  return -1;
}

// A map read back from GET /api/v1/maps/{id}/map.pgm plus its metadata. Pixel row 0 is the top
// (north) row, as in every PGM map.
struct GridMap {
  int width = 0;
  int height = 0;
  double resolution = 0.0;
  double origin_x = 0.0;
  double origin_y = 0.0;
  std::vector<std::uint8_t> pixels;

  bool valid() const {
    return width > 0 && height > 0 && resolution > 0.0 &&
           pixels.size() == static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  }
  double min_x() const { return origin_x; }
  double min_y() const { return origin_y; }
  double max_x() const { return origin_x + width * resolution; }
  double max_y() const { return origin_y + height * resolution; }
  // ROS map_server (negate 0): free when (255 - p) / 255 < free_thresh 0.196, i.e. p > 205.
  // Occupied and unknown cells are both "not free" here.
  bool free_pixel(int col, int row_from_bottom) const {
    const int image_row = height - 1 - row_from_bottom;
    return pixels[static_cast<std::size_t>(image_row) * width + col] > 205;
  }
  // Distance from (x, y) to the nearest cell that is not free (cell squares, not centres), capped
  // at `cap_m`; 0 outside the map.
  double clearance(double x, double y, double cap_m) const {
    if (x < min_x() || y < min_y() || x >= max_x() || y >= max_y()) return 0.0;
    const int reach = static_cast<int>(std::ceil(cap_m / resolution)) + 1;
    const int col0 = static_cast<int>(std::floor((x - origin_x) / resolution));
    const int row0 = static_cast<int>(std::floor((y - origin_y) / resolution));
    double best = cap_m;
    for (int row = row0 - reach; row <= row0 + reach; ++row) {
      for (int col = col0 - reach; col <= col0 + reach; ++col) {
        const double cell_x0 = origin_x + col * resolution;
        const double cell_y0 = origin_y + row * resolution;
        const double dx = std::max({cell_x0 - x, 0.0, x - (cell_x0 + resolution)});
        const double dy = std::max({cell_y0 - y, 0.0, y - (cell_y0 + resolution)});
        const double d = std::hypot(dx, dy);
        if (d >= best) continue;
        // Beyond the map counts as not free.
        const bool inside = col >= 0 && row >= 0 && col < width && row < height;
        if (!inside || !free_pixel(col, row)) best = d;
      }
    }
    return best;
  }
};

// Parses a binary PGM (P5, maxval <= 255, comments allowed). Returns false when it is not one.
inline bool parse_pgm(const std::string& bytes, int& width, int& height,
                      std::vector<std::uint8_t>& pixels) {
  std::size_t at = 0;
  auto token = [&]() -> std::string {
    while (at < bytes.size()) {
      if (bytes[at] == '#') {
        while (at < bytes.size() && bytes[at] != '\n') ++at;
      } else if (std::isspace(static_cast<unsigned char>(bytes[at]))) {
        ++at;
      } else {
        break;
      }
    }
    const std::size_t begin = at;
    while (at < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[at]))) ++at;
    return bytes.substr(begin, at - begin);
  };
  if (token() != "P5") return false;
  try {
    width = std::stoi(token());
    height = std::stoi(token());
    const int maxval = std::stoi(token());
    if (maxval <= 0 || maxval > 255) return false;
  } catch (const std::exception&) {
    return false;
  }
  ++at;  // the single whitespace after maxval
  const std::size_t count = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (width <= 0 || height <= 0 || at + count > bytes.size()) return false;
  pixels.assign(bytes.begin() + static_cast<std::ptrdiff_t>(at),
                bytes.begin() + static_cast<std::ptrdiff_t>(at + count));
  return true;
}

// The active map as served by the API (metadata + map.pgm).
inline GridMap fetch_active_map(const HttpClient& client) {
  GridMap map;
  const std::int64_t id = active_map_id(client);
  EXPECT_GT(id, 0) << "no active map";
  if (id <= 0) return map;
  const HttpReply meta = client.get("/api/v1/maps/" + std::to_string(id));
  EXPECT_EQ(meta.status, 200) << meta.body;
  const HttpReply pgm = client.get("/api/v1/maps/" + std::to_string(id) + "/map.pgm");
  EXPECT_EQ(pgm.status, 200) << pgm.body.substr(0, 200);
  if (meta.status != 200 || pgm.status != 200) return map;
  const json info = meta.json();
  EXPECT_TRUE(parse_pgm(pgm.body, map.width, map.height, map.pixels)) << "map.pgm is not a P5 PGM";
  EXPECT_EQ(map.width, info.at("width").get<int>());
  EXPECT_EQ(map.height, info.at("height").get<int>());
  map.resolution = info.at("resolution").get<double>();
  map.origin_x = info.at("origin").at("x").get<double>();
  map.origin_y = info.at("origin").at("y").get<double>();
  return map;
}

inline bool goal_finished(const json& goal) {
  const std::string status = goal.value("status", "");
  return status == "succeeded" || status == "failed" || status == "canceled";
}

// Polls GET /api/v1/goals/{id} until the goal has ended or `robot_timeout_s` of robot time has
// passed (a wall-clock cap guards a server whose clock stops). Returns the goal as last read.
inline json wait_goal_end(const HttpClient& client, std::int64_t id, double robot_timeout_s,
                          std::chrono::milliseconds wall_cap = std::chrono::milliseconds(0)) {
  const double start = robot_time(client);
  if (wall_cap.count() == 0) {
    wall_cap = std::chrono::milliseconds(static_cast<long>(robot_timeout_s * 1000.0)) + 30s;
  }
  json goal = json::object();
  const auto deadline = std::chrono::steady_clock::now() + wall_cap;
  const std::string target = "/api/v1/goals/" + std::to_string(id);
  while (std::chrono::steady_clock::now() < deadline) {
    const HttpReply reply = client.get(target);
    EXPECT_EQ(reply.status, 200) << reply.body;
    if (reply.status != 200) return goal;
    goal = reply.json();
    if (goal_finished(goal)) return goal;
    if (robot_time(client) > start + robot_timeout_s) return goal;
    std::this_thread::sleep_for(10ms);
  }
  return goal;
}

// POST /api/v1/goals with a heading.
inline HttpReply post_goal(const HttpClient& client, double x, double y, double theta) {
  return client.post("/api/v1/goals", json{{"x", x}, {"y", y}, {"theta", theta}});
}

// The events of a run (GET /api/v1/runs/{id}/events); `detail` is parsed when it is a string.
inline std::vector<json> run_events(const HttpClient& client, std::int64_t run_id) {
  const HttpReply reply = client.get("/api/v1/runs/" + std::to_string(run_id) + "/events");
  EXPECT_EQ(reply.status, 200) << reply.body;
  std::vector<json> events;
  if (reply.status != 200) return events;
  for (json event : reply.json()) {
    if (event.contains("detail") && event.at("detail").is_string()) {
      const json parsed = json::parse(event.at("detail").get<std::string>(), nullptr, false);
      if (!parsed.is_discarded()) event["detail"] = parsed;
    }
    events.push_back(std::move(event));
  }
  return events;
}

// The `goal` events of goal `id` in a run, oldest first.
inline std::vector<json> goal_events(const HttpClient& client, std::int64_t run_id,
                                     std::int64_t id) {
  std::vector<json> out;
  for (const auto& event : run_events(client, run_id)) {
    if (event.value("kind", "") != "goal" || !event.at("detail").is_object()) continue;
    if (event.at("detail").value("id", std::int64_t{-1}) == id) out.push_back(event);
  }
  return out;
}

// The current run's entry of GET /api/v1/runs.
inline json current_run(const HttpClient& client) {
  const std::int64_t id = current_run_id(client);
  const HttpReply reply = client.get("/api/v1/runs");
  if (reply.status != 200) return json::object();
  for (const auto& run : reply.json()) {
    if (run.at("id").get<std::int64_t>() == id) return run;
  }
  return json::object();
}

}  // namespace mobot::testing
