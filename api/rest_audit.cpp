// The audit trail of REST commands: every request that changes something and succeeds is a
// `command` event of the run, on disk before its response is sent.
#include <memory>

#include "api/rest_api.h"
#include "api/teleop_audit.h"

namespace mobot::api {
namespace {

// Request bodies up to this size are kept with the command; a map import's image is not.
constexpr std::size_t kMaxAuditedBodyBytes = 2048;

bool changes_something(http::verb method) {
  return method == http::verb::post || method == http::verb::put ||
         method == http::verb::patch || method == http::verb::delete_;
}

}  // namespace

Responder RestApi::audited(const Request& request, const std::optional<Caller>& caller,
                           const ClientContext& client, Responder respond) {
  const std::string_view path = target_path(request.target());
  // A drive is audited as its start and stop (audit_drive), not as each of its commands.
  if (!caller || !changes_something(request.method()) || !path.starts_with("/api/v1/") ||
      path == "/api/v1/teleop") {
    return respond;
  }
  CommandRecord record;
  record.command = std::string(request.method_string()) + " " + std::string(path);
  record.via = "rest";
  record.caller = *caller;
  record.address = client.address;
  record.client_id = client.id;
  if (request.body().size() <= kMaxAuditedBodyBytes) record.request_json = request.body();
  return [audit = &ports_.audit, record = std::move(record),
          respond = std::move(respond)](Response response) mutable {
    const unsigned status = response.result_int();
    if (status < 200 || status >= 300) return respond(std::move(response));
    record.status = static_cast<int>(status);
    auto held = std::make_shared<Response>(std::move(response));
    audit->record_command(std::move(record),
                          [respond = std::move(respond), held](Result<Done>) mutable {
                            respond(std::move(*held));
                          });
  };
}

Completion<msgs::Twist> RestApi::audit_drive(const Claimant& who, int ttl_ms,
                                             Completion<msgs::Twist> done) {
  return [audit = &ports_.audit, drives = &rest_drives_, who, ttl_ms,
          done = std::move(done)](Result<msgs::Twist> result) {
    if (result.ok()) {
      audit_drive_change(*audit, who,
                         drives->note(who.caller.token_id, result.value(), ttl_ms,
                                      TeleopLease::Clock::now()));
    }
    done(std::move(result));
  };
}

}  // namespace mobot::api
