// GET /api/v1/clients: every open connection, who it is and what it costs.
#include "api/rest_api.h"
#include "api/role_names.h"

namespace mobot::api {

std::optional<Caller> RestApi::identify_client(const Request& request,
                                               const ClientContext& client) {
  const std::string token = bearer_token(request);
  if (token.empty()) return std::nullopt;
  const auto caller = ports_.tokens.authenticate(token);
  if (!caller || client.id == 0) return caller;
  if (const auto record = hub_.clients().find(client.id)) record->identify(*caller);
  return caller;
}

Response RestApi::list_clients(const Request& request) const {
  nlohmann::json clients = nlohmann::json::array();
  for (const ClientRecord::View& client : hub_.clients().list()) {
    nlohmann::json entry{{"id", client.id},
                         {"kind", client.stream ? "stream" : "http"},
                         {"role", client.caller ? nlohmann::json(role_name(client.caller->role))
                                                : nlohmann::json(nullptr)},
                         {"label", client.caller ? nlohmann::json(client.caller->label)
                                                 : nlohmann::json(nullptr)},
                         {"address", client.address},
                         {"since", client.since_unix_s},
                         {"bytes_sent", client.bytes_sent},
                         {"dropped", client.dropped}};
    if (client.rtt_ms) entry["rtt_ms"] = *client.rtt_ms;
    if (client.stream) entry["topics"] = client.topics;
    clients.push_back(std::move(entry));
  }
  return json_response(request, http::status::ok, clients);
}

}  // namespace mobot::api
