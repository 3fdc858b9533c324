#include "api/api_error.h"
#include "api/json_request.h"
#include "api/rest_api.h"
#include "api/role_names.h"

namespace mobot::api {
namespace {

Role parse_role(const std::string& name) {
  if (name == "viewer") return Role::kViewer;
  if (name == "operator") return Role::kOperator;
  if (name == "admin") return Role::kAdmin;
  throw ApiError(400, "invalid_field", "'role' must be viewer, operator or admin");
}

}  // namespace

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
                        {"revoked", token.revoked}});
    }
    return json_response(request, http::status::ok, tokens);
  }
  if (path.size() == 3 && method == http::verb::post) {
    const nlohmann::json body = parse_json_body(request.body());
    const Role role = parse_role(require_string(body, "role", 16));
    std::string label;
    if (body.contains("label")) label = require_string(body, "label", 128);
    const auto [id, token] = ports_.tokens.create_token(role, label);
    return json_response(request, http::status::created,
                         {{"id", id}, {"role", role_name(role)}, {"token", token}});
  }
  if (path.size() == 4 && method == http::verb::delete_) {
    const auto id = parse_id(path[3]);
    if (!id || !ports_.tokens.revoke_token(*id)) {
      throw ApiError(404, "unknown_token", "no token with this id");
    }
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
