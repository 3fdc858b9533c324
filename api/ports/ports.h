#pragma once

#include "api/ports/audit_port.h"
#include "api/ports/camera_port.h"
#include "api/ports/control_port.h"
#include "api/ports/localization_port.h"
#include "api/ports/map_catalog_port.h"
#include "api/ports/mapping_port.h"
#include "api/ports/run_archive_port.h"
#include "api/ports/sim_control_port.h"
#include "api/ports/sweeps_port.h"
#include "api/ports/system_port.h"
#include "api/ports/token_admin_port.h"

namespace mobot::api {

// The doors from the API into the robot, one per role; the server implements them and the API
// never sees the server's classes. `sim` is null on the hardware backend.
struct Ports {
  ControlPort& control;
  MapCatalogPort& maps;
  MappingPort& mapping;
  LocalizationPort& localization;
  RunArchivePort& runs;
  TokenAdminPort& tokens;
  SweepsPort& sweeps;
  SystemPort& system;
  CameraPort& camera;
  AuditPort& audit;
  SimControlPort* sim = nullptr;
};

}  // namespace mobot::api
