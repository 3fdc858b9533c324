#include "api/api_error.h"
#include "api/json_request.h"
#include "api/rest_api.h"
#include "api/role_names.h"

namespace mobot::api {
namespace {

Role parse_role(const std::string& name) {
  if (const auto role = role_from_name(name)) return *role;
  throw ApiError(400, "invalid_field", "'role' must be viewer, operator or admin");
}

nlohmann::json expiry_json(const std::optional<std::int64_t>& expires_unix_s) {
  return expires_unix_s ? nlohmann::json(*expires_unix_s) : nlohmann::json(nullptr);
}

}  // namespace

Response RestApi::whoami(const Request& request) const {
  const Caller caller = require_role(request, Role::kViewer);
  std::optional<std::int64_t> expires_unix_s;
  for (const auto& token : ports_.tokens.list_tokens()) {
    if (token.id == caller.token_id) expires_unix_s = token.expires_unix_s;
  }
  return json_response(request, http::status::ok,
                       {{"token_id", caller.token_id},
                        {"label", caller.label},
                        {"role", role_name(caller.role)},
                        {"expires_at", expiry_json(expires_unix_s)}});
}

Response RestApi::route_tokens(const Request& request, const Segments& path) {
  require_role(request, Role::kAdmin);
  const auto method = request.method();
  if (path.size() == 3 && method == http::verb::get) {
    nlohmann::json tokens = nlohmann::json::array();
    for (const auto& token : ports_.tokens.list_tokens()) {
      tokens.push_back({{"id", token.id},
                        {"role", role_name(token.role)},
                        {"label", token.label},
                        {"created", token.created_unix_s},
                        {"expires_at", expiry_json(token.expires_unix_s)},
                        {"revoked", token.revoked}});
    }
    return json_response(request, http::status::ok, tokens);
  }
  if (path.size() == 3 && method == http::verb::post) {
    const nlohmann::json body = parse_json_body(request.body());
    const Role role = parse_role(require_string(body, "role", 16));
    std::string label;
    if (body.contains("label")) label = require_string(body, "label", kMaxTokenLabelChars);
    std::optional<std::int64_t> lifetime_s;
    if (const auto seconds =
            optional_integer(body, "expires_in_s", static_cast<int>(kMinTokenLifetime_s),
                             static_cast<int>(kMaxTokenLifetime_s))) {
      lifetime_s = *seconds;
    }
    const CreatedToken created = ports_.tokens.create_token(role, label, lifetime_s);
    return json_response(request, http::status::created,
                         {{"id", created.id},
                          {"role", role_name(role)},
                          {"token", created.token},
                          {"expires_at", expiry_json(created.expires_unix_s)}});
  }
  if (path.size() == 4 && method == http::verb::delete_) {
    const auto id = parse_id(path[3]);
    if (!id || !ports_.tokens.revoke_token(*id)) {
      throw ApiError(404, "unknown_token", "no token with this id");
    }
    // Its open streams close now, not at the next periodic check.
    hub_.close_inactive_tokens(
        [this](std::int64_t token_id) { return ports_.tokens.is_active(token_id); });
    Response response{http::status::no_content, request.version()};
    response.keep_alive(request.keep_alive());
    response.prepare_payload();
    return response;
  }
  if (path.size() == 3 || path.size() == 4) {
    throw ApiError(405, "method_not_allowed", "GET/POST /tokens, DELETE /tokens/{id}");
  }
  throw ApiError(404, "not_found", "no such endpoint");
}

}  // namespace mobot::api
