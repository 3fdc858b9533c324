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
#include "api/ports/ports.h"
#include "api/rest_reply.h"
#include "api/stream_hub.h"
#include "api/teleop_lease.h"

namespace mobot::api {

struct RestOptions {
  std::filesystem::path web_dir;
  std::string version;
};

// The REST API of docs/api.md and the dashboard's static files. handle() never throws: every
// failure becomes a JSON error response, and a refused request changes nothing. A request that
// waits for the robot (a command on the control loop, a read behind the recorder's commit) is
// answered from its port's Completion, on whichever thread that runs; the others are answered
// before handle() returns. The API, and the io_context its sessions run on, must outlive every
// Completion it handed out: the server stops whatever completes them before destroying either.
class RestApi {
 public:
  RestApi(const Ports& ports, StreamHub& hub, RestOptions options);

  // Sends the response to `request` through `respond`, exactly once, now or later. `client`: the
  // connection it came on (who holds the operator lock, who is connected).
  void handle(const Request& request, Responder respond, ClientContext client = {});
  // Who a stream upgrade request authenticates as (?token=), or nullopt.
  std::optional<Caller> stream_caller(const Request& request) const;

  // The largest body accepted for a request line, checked before the body is read.
  static std::size_t body_limit(http::verb method, std::string_view target);
  // The largest body_limit() of any request (map import).
  static constexpr std::size_t kMaxBodyLimit = 8 * 1024 * 1024;
  std::string metrics_text() const;
  void count_response(unsigned status);

 private:
  using Segments = std::vector<std::string_view>;

  Handled dispatch(const Request& request, const Replier& reply);
  Handled route(const Request& request, const Segments& path, const Replier& reply);
  Handled route_maps(const Request& request, const Segments& path, const Replier& reply);
  Handled route_runs(const Request& request, const Segments& path, const Replier& reply);
  Handled route_sim(const Request& request, const Segments& path, const Replier& reply);
  Handled route_sim_obstacles(const Request& request, const Segments& path, const Replier& reply);
  Response route_tokens(const Request& request, const Segments& path);
  Handled route_goals(const Request& request, const Segments& path, const Replier& reply);
  Handled route_goal(const Request& request, std::string_view id_text, const Replier& reply);
  Handled route_localization(const Request& request, const Segments& path, const Replier& reply);
  Handled route_mapping(const Request& request, const Segments& path, const Replier& reply);
  Handled route_zones(const Request& request, const Segments& path, std::int64_t map_id,
                      const Replier& reply);
  Handled route_sweeps(const Request& request, const Segments& path, const Replier& reply);
  Handled route_camera(const Request& request, const Segments& path, const Replier& reply);
  Handled route_tracking(const Request& request, const Segments& path, const Replier& reply);
  Handled route_follow(const Request& request, const Segments& path, const Replier& reply);
  Handled route_sim_targets(const Request& request, const Segments& path, const Replier& reply);
  Handled add_target(const Request& request, const Replier& reply);
  Handled remove_target(std::string_view id_text, const Replier& reply);
  // The robot's camera, or 404 no_camera.
  CameraDescription require_camera() const;
  Response route_sweep(const Request& request, const Segments& path);
  Response serve_static(const Request& request, std::string_view path) const;
  Caller require_role(const Request& request, Role needed) const;
  // A driving command (teleop, goals, follow): the operator role and the operator lock, which a
  // free lock gives at once; kConflict operator_busy while somebody else holds it.
  OperatorLock::Change require_driver(const Request& request, const Replier& reply);
  // The Completion of a driving command: one the robot refuses leaves the lock as it was.
  template <class T>
  Completion<T> undo_if_refused(const OperatorLock::Change& change, Completion<T> done) {
    return [lock = &hub_.operator_lock(), change, done = std::move(done)](Result<T> result) {
      if (!result.ok()) lock->undo(change);
      done(std::move(result));
    };
  }
  Response route_operator(const Request& request, const Segments& path, const Replier& reply);
  // The connection learns who its client is from any request that authenticates; who that is.
  std::optional<Caller> identify_client(const Request& request, const ClientContext& client);
  // `respond`, or for a command (a request that changes something) a responder that records a
  // successful one in the audit trail before it sends the response.
  Responder audited(const Request& request, const std::optional<Caller>& caller,
                    const ClientContext& client, Responder respond);
  // A teleop's Completion that notes the drive's start or stop in the audit trail.
  Completion<msgs::Twist> audit_drive(const Claimant& who, int ttl_ms,
                                      Completion<msgs::Twist> done);
  Response list_clients(const Request& request) const;
  // The caller's own token: what a dashboard shows after sign-in and how it knows itself in the
  // operator lock and the client list.
  Response whoami(const Request& request) const;

  Response health(const Request& request) const;
  Response robot(const Request& request) const;
  Handled teleop(const Request& request, const Replier& reply);
  Handled estop(const Request& request, const Replier& reply);
  Response metrics(const Request& request) const;
  Response openapi(const Request& request) const;

  Handled submit_goal(const Request& request, const Replier& reply);
  Handled set_pose(const Request& request, const Replier& reply);

  Response list_maps(const Request& request) const;
  Response import_map(const Request& request);
  Response map_info(const Request& request, std::int64_t id) const;
  Response map_export(const Request& request, std::int64_t id, std::string_view what) const;
  Handled activate_map(std::int64_t id, const Replier& reply);
  Response delete_map(const Request& request, std::int64_t id);

  Handled list_runs(const Replier& reply) const;
  Handled find_run(std::int64_t id, const Replier& reply) const;
  Handled run_trajectory(const Request& request, std::int64_t id, const Replier& reply) const;
  Handled run_events(std::int64_t id, const Replier& reply) const;

  Response list_worlds(const Request& request) const;
  Response sim_truth(const Request& request) const;
  Handled sim_reset(const Request& request, const Replier& reply);
  Response sim_clock(const Request& request);
  Handled add_obstacle(const Request& request, const Replier& reply);
  Handled remove_obstacle(std::string_view id_text, const Replier& reply);
  Handled kidnap(const Request& request, const Replier& reply);

  Handled start_sweep(const Request& request, const Replier& reply);
  Response sweep_cloud(const Request& request, std::int64_t id) const;

  Ports ports_;
  StreamHub& hub_;
  RestOptions options_;
  std::array<std::atomic<std::uint64_t>, 6> responses_by_class_{};
  TeleopLeases rest_drives_;  // the REST drives, for their audit

};

std::optional<std::int64_t> parse_id(std::string_view text);

}  // namespace mobot::api
