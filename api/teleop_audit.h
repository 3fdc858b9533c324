#pragma once

#include <string>

#include "api/operator_lock.h"
#include "api/ports/audit_port.h"
#include "api/teleop_lease.h"

namespace mobot::api {

// A command of `who` as the audit trail keeps it: who sent it, from where, over which channel.
CommandRecord command_record(const Claimant& who, std::string command);

// The audit trail keeps the start and the stop of a client's drive (TeleopLease), not each of its
// commands: a joystick sends twenty a second. Neither is waited for: a drive's commands are not
// held back for the disk, and the control loop records each lapse of a lease itself.
void audit_drive_change(AuditPort& audit, const Claimant& who, TeleopLease::Change change);

// A stream's drive that ended without a standing command: `reason` lease_lapsed, link_stalled or
// stream_closed.
void audit_drive_end(AuditPort& audit, const Claimant& who, std::string reason);

}  // namespace mobot::api
