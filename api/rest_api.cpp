#include "api/rest_api.h"

#include <cctype>
#include <charconv>

#include "api/api_error.h"
#include "api/frame_codec.h"
#include "api/json_request.h"
#include "api/openapi_document.h"
#include "api/prometheus_text.h"

namespace mobot::api {
namespace {

constexpr std::size_t kDefaultBodyLimit = 64 * 1024;
constexpr std::size_t kMapImportBodyLimit = RestApi::kMaxBodyLimit;

std::vector<std::string_view> split_path(std::string_view path) {
  std::vector<std::string_view> segments;
  while (!path.empty()) {
    const auto slash = path.find('/');
    const std::string_view segment = path.substr(0, slash);
    if (!segment.empty()) segments.push_back(segment);
    if (slash == std::string_view::npos) break;
    path.remove_prefix(slash + 1);
  }
  return segments;
}

[[noreturn]] void method_not_allowed() {
  throw ApiError(405, "method_not_allowed", "this method is not allowed on this path");
}

}  // namespace

std::optional<std::int64_t> parse_id(std::string_view text) {
  std::int64_t id = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), id);
  if (error != std::errc{} || end != text.data() + text.size() || id <= 0) return std::nullopt;
  return id;
}

RestApi::RestApi(const Ports& ports, StreamHub& hub, RestOptions options)
    : ports_(ports), hub_(hub), options_(std::move(options)) {}

std::size_t RestApi::body_limit(http::verb method, std::string_view target) {
  const std::string_view path = target_path(target);
  if (method == http::verb::post && (path == "/api/v1/maps" || path == "/api/v1/maps/")) {
    return kMapImportBodyLimit;
  }
  return kDefaultBodyLimit;
}

void RestApi::handle(const Request& request, Responder respond, ClientContext client) {
  const std::optional<Caller> caller = identify_client(request, client);
  Responder counted = [this, respond = std::move(respond)](Response response) {
    count_response(response.result_int());
    respond(std::move(response));
  };
  Responder respond_audited = audited(request, caller, client, std::move(counted));
  const Replier reply(request, std::move(respond_audited), std::move(client));
  reply.answer([&] { return dispatch(request, reply); });
}

Handled RestApi::dispatch(const Request& request, const Replier& reply) {
  const std::string_view path = target_path(request.target());
  if (path == "/metrics" || path.starts_with("/api/")) {
    return route(request, split_path(path), reply);
  }
  return serve_static(request, path);
}

void RestApi::count_response(unsigned status) {
  const std::size_t status_class = std::min<std::size_t>(status / 100, 5);
  responses_by_class_[status_class].fetch_add(1, std::memory_order_relaxed);
}

Caller RestApi::require_role(const Request& request, Role needed) const {
  const std::string token = bearer_token(request);
  if (token.empty()) throw ApiError(401, "unauthorized", "missing bearer token");
  const auto caller = ports_.tokens.authenticate(token);
  if (!caller) throw ApiError(401, "unauthorized", "unknown token");
  if (caller->role < needed) {
    throw ApiError(
        403, "forbidden",
        needed == Role::kAdmin ? "this needs the admin role" : "this needs the operator role");
  }
  return *caller;
}

std::optional<Caller> RestApi::stream_caller(const Request& request) const {
  const std::string token = query_parameter(request.target(), "token");
  if (token.empty()) return std::nullopt;
  return ports_.tokens.authenticate(token);
}

Handled RestApi::route(const Request& request, const Segments& path, const Replier& reply) {
  const auto method = request.method();
  if (path.size() == 1 && path[0] == "metrics") {
    if (method != http::verb::get) method_not_allowed();
    require_role(request, Role::kViewer);
    return metrics(request);
  }
  if (path.size() < 3 || path[0] != "api" || path[1] != "v1") {
    throw ApiError(404, "not_found", "no such endpoint");
  }
  const std::string_view resource = path[2];
  if (resource == "health" && path.size() == 3) {
    if (method != http::verb::get) method_not_allowed();
    return health(request);
  }
  if (resource == "maps") return route_maps(request, path, reply);
  if (resource == "runs") return route_runs(request, path, reply);
  if (resource == "sim" || resource == "worlds") return route_sim(request, path, reply);
  if (resource == "tokens") return route_tokens(request, path);
  if (resource == "goals") return route_goals(request, path, reply);
  if (resource == "localization") return route_localization(request, path, reply);
  if (resource == "mapping") return route_mapping(request, path, reply);
  if (resource == "sweeps") return route_sweeps(request, path, reply);
  if (resource == "camera") return route_camera(request, path, reply);
  if (resource == "tracking") return route_tracking(request, path, reply);
  if (resource == "follow") return route_follow(request, path, reply);
  if (path.size() != 3) throw ApiError(404, "not_found", "no such endpoint");
  if (resource == "robot") {
    if (method != http::verb::get) method_not_allowed();
    require_role(request, Role::kViewer);
    return robot(request);
  }
  if (resource == "whoami") {
    if (method != http::verb::get) method_not_allowed();
    return whoami(request);
  }
  if (resource == "openapi.json") {
    if (method != http::verb::get) method_not_allowed();
    require_role(request, Role::kViewer);
    return openapi(request);
  }
  if (resource == "teleop") {
    if (method != http::verb::post) method_not_allowed();
    require_role(request, Role::kOperator);
    return teleop(request, reply);
  }
  if (resource == "operator") return route_operator(request, path, reply);
  if (resource == "clients" && path.size() == 3) {
    if (method != http::verb::get) method_not_allowed();
    require_role(request, Role::kAdmin);
    return list_clients(request);
  }
  if (resource == "estop") {
    if (method != http::verb::post) method_not_allowed();
    require_role(request, Role::kOperator);
    return estop(request, reply);
  }
  throw ApiError(404, "not_found", "no such endpoint");
}

Response RestApi::health(const Request& request) const {
  return json_response(request, http::status::ok,
                       {{"status", "ok"},
                        {"version", options_.version},
                        {"backend", ports_.system.backend_name()},
                        {"uptime_s", ports_.system.uptime_s()}});
}

Response RestApi::robot(const Request& request) const {
  return json_response(request, http::status::ok, snapshot_json(ports_.control.snapshot()));
}

Handled RestApi::teleop(const Request& request, const Replier& reply) {
  const TeleopRequest command = parse_teleop(parse_json_body(request.body()));
  const OperatorLock::Change lock = require_driver(request, reply);
  ports_.control.teleop(
      command.twist, command.ttl_ms,
      undo_if_refused(lock, audit_drive(lock.after.claimant, command.ttl_ms,
                                        reply.completion<msgs::Twist>(
                                            [](const Request& head, const msgs::Twist& applied) {
                                              return json_response(head, http::status::ok,
                                                                   {{"v", applied.linear_mps},
                                                                    {"w", applied.angular_radps}});
                                            }))));
  return kReplyLater;
}

Handled RestApi::estop(const Request& request, const Replier& reply) {
  const bool engaged = require_bool(parse_json_body(request.body()), "engaged");
  ports_.control.set_estop(engaged, reply.completion<bool>([](const Request& head, bool state) {
    return json_response(head, http::status::ok, {{"estop", state}});
  }));
  return kReplyLater;
}

Response RestApi::metrics(const Request& request) const {
  return bytes_response(request, http::status::ok, "text/plain; version=0.0.4",
                        metrics_text() + hub_.metrics_text() + ports_.system.metrics_text());
}

std::string RestApi::metrics_text() const {
  std::string out;
  append_family(out, "mobot_http_responses_total", "counter", "HTTP responses by status class.");
  for (std::size_t status_class = 1; status_class <= 5; ++status_class) {
    append_sample(out, "mobot_http_responses_total",
                  static_cast<double>(responses_by_class_[status_class].load()),
                  "code=\"" + std::to_string(status_class) + "xx\"");
  }
  return out;
}

Response RestApi::openapi(const Request& request) const {
  return bytes_response(request, http::status::ok, "application/json",
                        std::string(openapi_document()));
}

}  // namespace mobot::api
