#pragma once

#include <cstdint>
#include <string>

#include "api/ports/result.h"
#include "api/ports/token_admin_port.h"

namespace mobot::api {

// One command as the audit trail keeps it: what was asked, by whom, from where.
struct CommandRecord {
  std::string command;  // "POST /api/v1/goals", "teleop_start", "estop", ...
  std::string via;      // "rest" or "stream"
  Caller caller;
  std::string address;  // the client's "ip:port"
  std::uint64_t client_id = 0;
  int status = 0;            // the HTTP status a REST command was answered with
  std::string request_json;  // the request's JSON when small enough to keep, else empty
  std::string reason;        // why a teleop ended (teleop_stop), else empty
};

// The run's audit trail: every command a client sends is an event of the run. Thread-safe.
class AuditPort {
 public:
  virtual ~AuditPort() = default;

  // Records `record` as a `command` event of the current run and completes once it is on disk,
  // so that a command acknowledged after this is in the trail even if the server dies next.
  virtual void record_command(CommandRecord record, Completion<Done> done) = 0;
};

}  // namespace mobot::api
