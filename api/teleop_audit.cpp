#include "api/teleop_audit.h"

namespace mobot::api {
namespace {

void record_drive(AuditPort& audit, const Claimant& who, std::string command, std::string reason) {
  CommandRecord record = command_record(who, std::move(command));
  record.reason = std::move(reason);
  audit.record_command(std::move(record), [](Result<Done>) {});
}

}  // namespace

CommandRecord command_record(const Claimant& who, std::string command) {
  CommandRecord record;
  record.command = std::move(command);
  record.via = who.stream ? "stream" : "rest";
  record.caller = who.caller;
  record.address = who.address;
  record.client_id = who.client_id;
  return record;
}

void audit_drive_change(AuditPort& audit, const Claimant& who, TeleopLease::Change change) {
  if (change == TeleopLease::Change::kStarted) record_drive(audit, who, "teleop_start", "");
  if (change == TeleopLease::Change::kStopped) record_drive(audit, who, "teleop_stop", "released");
}

void audit_drive_end(AuditPort& audit, const Claimant& who, std::string reason) {
  record_drive(audit, who, "teleop_stop", std::move(reason));
}

}  // namespace mobot::api
