// The operator lock over REST: GET /api/v1/operator, POST /api/v1/operator {"action"}, and the
// check every driving command makes.
#include "api/api_error.h"
#include "api/json_request.h"
#include "api/rest_api.h"
#include "api/role_names.h"
#include "api/wall_clock.h"

namespace mobot::api {
namespace {

nlohmann::json holder_json(const std::optional<OperatorHolder>& holder) {
  if (!holder) return {{"holder", nullptr}};
  const Claimant& who = holder->claimant;
  return {{"holder",
           {{"client_id", who.client_id},
            {"token_id", who.caller.token_id},
            {"label", who.caller.label},
            {"role", role_name(who.caller.role)},
            {"address", who.address},
            {"since", holder->since_unix_s}}}};
}

Claimant claimant_of(const Caller& caller, const ClientContext& client) {
  return {caller, client.id, false, client.address};
}

template <class T>
const T& granted(const Result<T>& result) {
  if (!result.ok()) throw DomainException(result.error());
  return result.value();
}

}  // namespace

OperatorLock::Change RestApi::require_driver(const Request& request, const Replier& reply) {
  const Caller caller = require_role(request, Role::kOperator);
  return granted(hub_.operator_lock().claim(claimant_of(caller, reply.client()),
                                            OperatorLock::Clock::now(), unix_now_s()));
}

Response RestApi::route_operator(const Request& request, const Segments& path,
                                 const Replier& reply) {
  if (path.size() != 3) throw ApiError(404, "not_found", "no such endpoint");
  const auto now = OperatorLock::Clock::now();
  if (request.method() == http::verb::get) {
    require_role(request, Role::kViewer);
    return json_response(request, http::status::ok, holder_json(hub_.operator_lock().holder(now)));
  }
  if (request.method() != http::verb::post) {
    throw ApiError(405, "method_not_allowed", "use GET or POST on /api/v1/operator");
  }
  const Caller caller = require_role(request, Role::kOperator);
  const std::string action = require_string(parse_json_body(request.body()), "action", 16);
  const Claimant who = claimant_of(caller, reply.client());
  if (action == "acquire") {
    granted(hub_.operator_lock().acquire(who, now, unix_now_s()));
  } else if (action == "release") {
    granted(hub_.operator_lock().release(who, now));
  } else if (action == "take_over") {
    if (caller.role < Role::kAdmin) throw ApiError(403, "forbidden", "take_over needs the admin role");
    granted(hub_.operator_lock().take_over(who, now, unix_now_s()));
  } else {
    throw ApiError(400, "invalid_field", "'action' must be acquire, release or take_over");
  }
  return json_response(request, http::status::ok, holder_json(hub_.operator_lock().holder(now)));
}

}  // namespace mobot::api
