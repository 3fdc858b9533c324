#include <cstdio>

#include "api/api_error.h"
#include "api/rest_api.h"

namespace mobot::api {
namespace {

[[noreturn]] void unknown_run() { throw ApiError(404, "unknown_run", "no run with this id"); }

nlohmann::json run_json(const RunInfo& run) {
  nlohmann::json json{{"id", run.id},
                      {"name", run.name},
                      {"started", run.started_unix_s},
                      {"distance_m", run.distance_m},
                      {"goals",
                       {{"succeeded", run.goals_succeeded},
                        {"failed", run.goals_failed},
                        {"canceled", run.goals_canceled}}}};
  if (run.ended_unix_s) json["ended"] = *run.ended_unix_s;
  return json;
}

std::string trajectory_csv(const std::vector<TrajectoryPoint>& points) {
  std::string csv = "t,x,y,theta\n";
  char line[128];
  for (const auto& p : points) {
    const int length = std::snprintf(line, sizeof line, "%.3f,%.4f,%.4f,%.5f\n", p.t_s, p.x, p.y,
                                     p.theta);
    csv.append(line, static_cast<std::size_t>(length));
  }
  return csv;
}

}  // namespace

Response RestApi::route_runs(const Request& request, const Segments& path) {
  if (request.method() != http::verb::get) {
    throw ApiError(405, "method_not_allowed", "runs are read-only");
  }
  require_role(request, Role::kViewer);
  if (path.size() == 3) return list_runs(request);
  const auto id = parse_id(path[3]);
  if (path.size() == 4) {
    for (const auto& run : port_.list_runs()) {
      if (id && run.id == *id) return json_response(request, http::status::ok, run_json(run));
    }
    unknown_run();
  }
  if (path.size() == 5 && path[4] == "trajectory") {
    if (!id) unknown_run();
    return run_trajectory(request, *id);
  }
  if (path.size() == 5 && path[4] == "events") {
    if (!id) unknown_run();
    return run_events(request, *id);
  }
  throw ApiError(404, "not_found", "no such endpoint");
}

Response RestApi::list_runs(const Request& request) const {
  nlohmann::json runs = nlohmann::json::array();
  for (const auto& run : port_.list_runs()) runs.push_back(run_json(run));
  return json_response(request, http::status::ok, runs);
}

Response RestApi::run_trajectory(const Request& request, std::int64_t id) const {
  std::string format = query_parameter(request.target(), "format");
  if (format.empty()) format = "json";
  if (format != "json" && format != "csv") {
    throw ApiError(400, "invalid_format", "format is json or csv");
  }
  const auto points = port_.run_trajectory(id);
  if (!points) unknown_run();
  if (format == "csv") {
    Response response = bytes_response(request, http::status::ok, "text/csv", trajectory_csv(*points));
    response.set(http::field::content_disposition,
                 "attachment; filename=\"run-" + std::to_string(id) + ".csv\"");
    return response;
  }
  nlohmann::json json = nlohmann::json::array();
  for (const auto& p : *points) {
    json.push_back({{"t", p.t_s}, {"x", p.x}, {"y", p.y}, {"theta", p.theta}});
  }
  return json_response(request, http::status::ok, json);
}

Response RestApi::run_events(const Request& request, std::int64_t id) const {
  const auto events = port_.run_events(id);
  if (!events) unknown_run();
  nlohmann::json json = nlohmann::json::array();
  for (const auto& event : *events) {
    nlohmann::json detail = nlohmann::json::parse(event.detail_json, nullptr, false);
    if (detail.is_discarded()) detail = event.detail_json;
    json.push_back({{"t", event.t_s}, {"kind", event.kind}, {"detail", std::move(detail)}});
  }
  return json_response(request, http::status::ok, json);
}

}  // namespace mobot::api
