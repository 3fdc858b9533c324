#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "api/http_types.h"
#include "api/robot_port.h"
#include "api/stream_hub.h"

namespace mobot::api {

struct RestOptions {
  std::filesystem::path web_dir;
  std::string version;
};

// The REST API of CONTRACT.md and the dashboard's static files. handle() never throws: every
// failure becomes a JSON error response, and a refused request changes nothing.
class RestApi {
 public:
  RestApi(RobotPort& port, StreamHub& hub, RestOptions options);

  Response handle(const Request& request);
  // The role a stream upgrade request authenticates as (?token=), or nullopt.
  std::optional<Role> stream_role(const Request& request) const;
  // The largest body accepted for a request line, checked before the body is read.
  static std::size_t body_limit(http::verb method, std::string_view target);
  // The largest body_limit() of any request (map import).
  static constexpr std::size_t kMaxBodyLimit = 8 * 1024 * 1024;
  std::string metrics_text() const;
  void count_response(unsigned status);

 private:
  using Segments = std::vector<std::string_view>;

  Response route(const Request& request, const Segments& path);
  Response route_maps(const Request& request, const Segments& path);
  Response route_runs(const Request& request, const Segments& path);
  Response route_sim(const Request& request, const Segments& path);
  Response route_tokens(const Request& request, const Segments& path);
  Response route_goals(const Request& request, const Segments& path);
  Response route_localization(const Request& request, const Segments& path);
  Response route_sweeps(const Request& request, const Segments& path);
  Response serve_static(const Request& request, std::string_view path) const;
  Role require_role(const Request& request, Role needed) const;

  Response health(const Request& request) const;
  Response robot(const Request& request) const;
  Response teleop(const Request& request);
  Response estop(const Request& request);
  Response metrics(const Request& request) const;
  Response openapi(const Request& request) const;

  Response list_maps(const Request& request) const;
  Response import_map(const Request& request);
  Response map_info(const Request& request, std::int64_t id) const;
  Response map_export(const Request& request, std::int64_t id, std::string_view what) const;
  Response activate_map(const Request& request, std::int64_t id);
  Response delete_map(const Request& request, std::int64_t id);

  Response list_runs(const Request& request) const;
  Response run_trajectory(const Request& request, std::int64_t id) const;
  Response run_events(const Request& request, std::int64_t id) const;

  Response sim_reset(const Request& request);
  Response sim_clock(const Request& request);
  Response add_obstacle(const Request& request);

  RobotPort& port_;
  StreamHub& hub_;
  RestOptions options_;
  std::array<std::atomic<std::uint64_t>, 6> responses_by_class_{};
};

std::optional<std::int64_t> parse_id(std::string_view text);

}  // namespace mobot::api
