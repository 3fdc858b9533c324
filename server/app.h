#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ssl/context.hpp>
#include <optional>

#include "api/http_server.h"
#include "api/ports/ports.h"
#include "api/rest_api.h"
#include "api/stream_hub.h"
#include "db/database.h"
#include "db/map_store.h"
#include "db/run_store.h"
#include "db/sweep_store.h"
#include "db/token_store.h"
#include "db/zone_store.h"
#include "server/bus.h"
#include "server/config.h"
#include "server/recorder.h"
#include "server/robot_assembly.h"
#include "server/services/control_service.h"
#include "server/services/localization_service.h"
#include "server/services/map_catalog.h"
#include "server/services/mapping_service.h"
#include "server/services/run_archive.h"
#include "server/services/camera_service.h"
#include "server/services/command_audit.h"
#include "server/services/sim_service.h"
#include "server/services/token_admin.h"
#include "server/sweeps.h"

namespace mobot::server {

// mobotd: wires the store, the robot, its services (one per API role port) and the HTTP/WebSocket
// server, and says what the server is (the SystemPort).
class App final : public api::SystemPort {
 public:
  explicit App(Config config);
  ~App() override;

  // Listens, prints the ready line, and serves until SIGINT/SIGTERM; returns the exit code.
  int run();

  std::string backend_name() const override { return config_.backend; }
  double uptime_s() const override;
  std::string metrics_text() const override;

 private:
  void ensure_admin_token();
  api::Ports ports();
  void wait_for_first_tick();
  void shut_down();

  Config config_;
  // Loaded first: a certificate or key that does not load stops mobotd before anything starts.
  std::optional<boost::asio::ssl::context> tls_;
  db::Database database_;
  // The store again, for the token checks of every request alone (db/token_store.h).
  db::Database token_lookups_;
  db::MapStore maps_;
  db::ZoneStore zones_;
  db::RunStore runs_;
  db::TokenStore tokens_;
  db::SweepStore sweep_store_;
  std::chrono::steady_clock::time_point started_;
  Bus bus_;
  api::StreamHub hub_;
  std::unique_ptr<Recorder> recorder_;
  std::unique_ptr<Sweeps> sweeps_;
  std::unique_ptr<RobotAssembly> robot_;
  std::unique_ptr<ControlService> control_;
  std::unique_ptr<MapCatalog> map_catalog_;
  std::unique_ptr<MappingService> mapping_;
  std::unique_ptr<LocalizationService> localization_;
  std::unique_ptr<RunArchive> run_archive_;
  std::unique_ptr<CommandAudit> audit_;
  std::unique_ptr<TokenAdmin> token_admin_;
  std::unique_ptr<SimService> sim_;
  std::unique_ptr<CameraService> camera_;
  std::unique_ptr<api::RestApi> rest_;
  boost::asio::io_context io_;
  std::unique_ptr<api::HttpServer> http_;
  std::vector<std::thread> io_threads_;
  bool stopped_ = false;
};

}  // namespace mobot::server
