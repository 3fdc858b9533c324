#include <algorithm>
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
    const int length =
        std::snprintf(line, sizeof line, "%.3f,%.4f,%.4f,%.5f\n", p.t_s, p.x, p.y, p.theta);
    csv.append(line, static_cast<std::size_t>(length));
  }
  return csv;
}

Response trajectory_csv_response(const Request& head, std::int64_t id,
                                 const std::vector<TrajectoryPoint>& points) {
  Response response = bytes_response(head, http::status::ok, "text/csv", trajectory_csv(points));
  response.set(http::field::content_disposition,
               "attachment; filename=\"run-" + std::to_string(id) + ".csv\"");
  return response;
}

Response trajectory_json_response(const Request& head, const std::vector<TrajectoryPoint>& points) {
  nlohmann::json json = nlohmann::json::array();
  for (const auto& p : points) {
    json.push_back({{"t", p.t_s}, {"x", p.x}, {"y", p.y}, {"theta", p.theta}});
  }
  return json_response(head, http::status::ok, json);
}

nlohmann::json event_json(const RunEvent& event) {
  // The detail is stored as the JSON text it was recorded as; text that is not JSON goes out as a
  // string.
  nlohmann::json detail = nlohmann::json::parse(event.detail_json, nullptr, false);
  if (detail.is_discarded()) detail = event.detail_json;
  return {{"t", event.t_s}, {"kind", event.kind}, {"detail", std::move(detail)}};
}

}  // namespace

Handled RestApi::route_runs(const Request& request, const Segments& path, const Replier& reply) {
  if (request.method() != http::verb::get) {
    throw ApiError(405, "method_not_allowed", "runs are read-only");
  }
  require_role(request, Role::kViewer);
  if (path.size() == 3) return list_runs(reply);
  const auto id = parse_id(path[3]);
  if (path.size() == 4) {
    if (!id) unknown_run();
    return find_run(*id, reply);
  }
  if (path.size() == 5 && path[4] == "trajectory") {
    if (!id) unknown_run();
    return run_trajectory(request, *id, reply);
  }
  if (path.size() == 5 && path[4] == "events") {
    if (!id) unknown_run();
    return run_events(*id, reply);
  }
  throw ApiError(404, "not_found", "no such endpoint");
}

Handled RestApi::list_runs(const Replier& reply) const {
  ports_.runs.list_runs(reply.completion<std::vector<RunInfo>>(
      [](const Request& head, const std::vector<RunInfo>& runs) {
        nlohmann::json json = nlohmann::json::array();
        for (const auto& run : runs) json.push_back(run_json(run));
        return json_response(head, http::status::ok, json);
      }));
  return kReplyLater;
}

Handled RestApi::find_run(std::int64_t id, const Replier& reply) const {
  ports_.runs.list_runs(reply.completion<std::vector<RunInfo>>(
      [id](const Request& head, const std::vector<RunInfo>& runs) {
        const auto run =
            std::find_if(runs.begin(), runs.end(), [id](const RunInfo& r) { return r.id == id; });
        if (run == runs.end()) unknown_run();
        return json_response(head, http::status::ok, run_json(*run));
      }));
  return kReplyLater;
}

Handled RestApi::run_trajectory(const Request& request, std::int64_t id,
                                const Replier& reply) const {
  std::string format = query_parameter(request.target(), "format");
  if (format.empty()) format = "json";
  if (format != "json" && format != "csv") {
    throw ApiError(400, "invalid_format", "format is json or csv");
  }
  ports_.runs.run_trajectory(
      id, reply.completion<std::vector<TrajectoryPoint>>(
              [id, csv = format == "csv"](const Request& head,
                                          const std::vector<TrajectoryPoint>& points) {
                return csv ? trajectory_csv_response(head, id, points)
                           : trajectory_json_response(head, points);
              }));
  return kReplyLater;
}

Handled RestApi::run_events(std::int64_t id, const Replier& reply) const {
  ports_.runs.run_events(id, reply.completion<std::vector<RunEvent>>(
                                 [](const Request& head, const std::vector<RunEvent>& events) {
                                   nlohmann::json json = nlohmann::json::array();
                                   for (const auto& event : events)
                                     json.push_back(event_json(event));
                                   return json_response(head, http::status::ok, json);
                                 }));
  return kReplyLater;
}

}  // namespace mobot::api
