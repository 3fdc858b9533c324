#include "server/services/command_audit.h"

#include <nlohmann/json.hpp>

#include "api/role_names.h"
#include "server/services/after_commit.h"

namespace mobot::server {
namespace {

nlohmann::json command_detail(const api::CommandRecord& record) {
  nlohmann::json detail{{"command", record.command},
                        {"via", record.via},
                        {"token_id", record.caller.token_id},
                        {"label", record.caller.label},
                        {"role", api::role_name(record.caller.role)},
                        {"address", record.address},
                        {"client_id", record.client_id}};
  if (record.status != 0) detail["status"] = record.status;
  if (!record.reason.empty()) detail["reason"] = record.reason;
  if (!record.request_json.empty()) {
    // The API keeps only request bodies it parsed as JSON; one that does not parse is left out
    // rather than stored as a string nobody can query.
    nlohmann::json request = nlohmann::json::parse(record.request_json, nullptr, false);
    if (!request.is_discarded()) detail["request"] = std::move(request);
  }
  return detail;
}

}  // namespace

void CommandAudit::record_command(api::CommandRecord record, api::Completion<api::Done> done) {
  runtime_.post([this, detail = command_detail(record),
                 done = std::move(done)](TickContext& context) mutable {
    context.event("command", std::move(detail));
    after_commit(recorder_, context, std::move(done), api::Done{});
  });
}

}  // namespace mobot::server
