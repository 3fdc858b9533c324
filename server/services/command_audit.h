#pragma once

#include "api/ports/audit_port.h"
#include "server/recorder.h"
#include "server/runtime.h"

namespace mobot::server {

// The AuditPort: a command is a `command` event of the run, recorded between ticks like the
// events of the command itself (so the trail and the run agree on the order and the robot time)
// and committed before the caller is told.
class CommandAudit final : public api::AuditPort {
 public:
  CommandAudit(Runtime& runtime, Recorder& recorder) : runtime_(runtime), recorder_(recorder) {}

  void record_command(api::CommandRecord record, api::Completion<api::Done> done) override;

 private:
  Runtime& runtime_;
  Recorder& recorder_;
};

}  // namespace mobot::server
