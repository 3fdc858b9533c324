#include "server/app.h"

#include "server/wall_clock.h"

#include <spdlog/spdlog.h>
#include <sys/stat.h>

#include <boost/asio/signal_set.hpp>
#include <fstream>
#include <iostream>

#include "api/prometheus_text.h"
#include "api/tls_context.h"
#include "drivers/backend_factory.h"
#include "server/bus_bridges.h"
#include "server/data_dir.h"

namespace mobot::server {
namespace {

std::filesystem::path web_dir_of(const Config& config) {
  return config.server.web_dir.empty() ? std::filesystem::path(MOBOT_DEFAULT_WEB_DIR)
                                       : config.server.web_dir;
}

std::string default_run_name() {
  const std::time_t now = std::time(nullptr);
  char text[64];
  std::strftime(text, sizeof text, "run %Y-%m-%d %H:%M:%S", std::localtime(&now));
  return text;
}

api::StreamOptions stream_options(const Config& config) {
  api::StreamOptions options;
  options.max_frames_per_topic = static_cast<std::size_t>(config.stream.max_frames_per_topic);
  options.simulated = config.backend == "sim";
  auto rate = [&](api::TopicId topic) -> double& {
    return options.nominal_rate_hz[api::topic_index(topic)];
  };
  rate(api::TopicId::kPose) = config.robot.control_rate_hz;
  rate(api::TopicId::kOdom) = config.robot.control_rate_hz;
  rate(api::TopicId::kTruth) = config.robot.control_rate_hz;
  rate(api::TopicId::kScan) = config.robot.laser_rate_hz;
  rate(api::TopicId::kSonar) = config.robot.sonar_rate_hz;
  rate(api::TopicId::kStatus) = 1.0;
  return options;
}

db::Database open_database(const Config& config) {
  std::filesystem::create_directories(config.server.data_dir);
  return db::Database::open(store_path(config.server.data_dir));
}

// The real devices' counters, one sample per device of each metric.
std::string device_metrics_text(const std::vector<drivers::DeviceCounters>& devices) {
  struct Metric {
    const char* name;
    const char* type;
    const char* help;
    double (*value)(const drivers::DeviceCounters&);
  };
  static constexpr Metric kMetrics[] = {
      {"mobot_device_ok", "gauge", "The device answers as it should (1) or not (0).",
       [](const drivers::DeviceCounters& d) { return d.status.ok ? 1.0 : 0.0; }},
      {"mobot_device_bytes_total", "counter", "Bytes received from the device.",
       [](const drivers::DeviceCounters& d) { return static_cast<double>(d.bytes); }},
      {"mobot_device_frames_total", "counter", "Complete replies, packets or scans received.",
       [](const drivers::DeviceCounters& d) { return static_cast<double>(d.frames); }},
      {"mobot_device_checksum_errors_total", "counter",
       "Frames that failed their checksum or did not parse.",
       [](const drivers::DeviceCounters& d) { return static_cast<double>(d.checksum_errors); }},
      {"mobot_device_reconnects_total", "counter", "Times the device was reopened after a fault.",
       [](const drivers::DeviceCounters& d) { return static_cast<double>(d.reconnects); }},
  };
  std::string out;
  bool first_battery = true;
  for (const drivers::DeviceCounters& device : devices) {
    if (!device.battery_v) continue;
    const std::string labels = "device=\"" + device.name + "\"";
    if (first_battery) {
      api::append_metric(out, "mobot_battery_volts", "gauge", "The base's battery voltage.",
                         *device.battery_v, labels);
    } else {
      api::append_sample(out, "mobot_battery_volts", *device.battery_v, labels);
    }
    first_battery = false;
  }
  for (const Metric& metric : kMetrics) {
    for (std::size_t i = 0; i < devices.size(); ++i) {
      const std::string labels = "device=\"" + devices[i].name + "\"";
      if (i == 0) {
        api::append_metric(out, metric.name, metric.type, metric.help, metric.value(devices[i]),
                           labels);
      } else {
        api::append_sample(out, metric.name, metric.value(devices[i]), labels);
      }
    }
  }
  return out;
}

std::optional<boost::asio::ssl::context> tls_context_of(const Config& config) {
  if (!config.server.tls()) return std::nullopt;
  try {
    return api::make_tls_server_context({config.server.tls_cert, config.server.tls_key});
  } catch (const api::TlsSetupError& error) {
    throw ConfigError(std::string("server.tls: ") + error.what());
  }
}

drivers::BackendOptions backend_options(const Config& config) {
  drivers::BackendOptions options;
  options.backend = config.backend;
  options.profile = config.robot.profile;
  options.world = config.sim.world;
  options.worlds_dir = config.sim.worlds_dir;
  options.seed = config.sim.seed;
  options.laser_rate_hz = config.robot.laser_rate_hz;
  options.sonar_rate_hz = config.robot.sonar_rate_hz;
  options.compass_rate_hz = config.robot.compass_rate_hz;
  options.odometry_errors = config.sim.odometry;
  options.omni_pixels = config.sim.omni_pixels;
  if (config.document && config.document["hardware"])
    options.hardware = config.document["hardware"];
  options.control_rate_hz = config.robot.control_rate_hz;
  return options;
}

}  // namespace

App::App(Config config)
    : config_(std::move(config)),
      tls_(tls_context_of(config_)),
      database_(open_database(config_)),
      token_lookups_(open_database(config_)),
      maps_(database_),
      zones_(database_),
      runs_(database_),
      tokens_(database_, token_lookups_),
      sweep_store_(database_),
      started_(std::chrono::steady_clock::now()),
      hub_(stream_options(config_)) {
  std::unique_ptr<drivers::Backend> backend = drivers::make_backend(backend_options(config_));
  token_admin_ = std::make_unique<TokenAdmin>(tokens_, config_.extra_admin_token);
  ensure_admin_token();

  runs_.close_dangling_runs(unix_now_s());
  const std::string run_name = config_.run_name.empty() ? default_run_name() : config_.run_name;
  const std::int64_t run_id = runs_.start_run(run_name, unix_now_s());
  recorder_ = std::make_unique<Recorder>(runs_, run_id, config_.recorder.flush_period_ms);
  connect_stream_hub(bus_, hub_);
  connect_recorder(bus_, *recorder_, config_.recorder.trajectory_rate_hz);

  const kinematics::RobotGeometry geometry = backend->geometry();
  robot_ = std::make_unique<RobotAssembly>(
      config_, bus_, std::move(backend),
      [this](SweepOutcome outcome) { sweeps_->on_outcome(std::move(outcome)); });
  sweeps_ = std::make_unique<Sweeps>(
      config_.sweeps, SweepRobot{geometry.height_m, geometry.footprint_width_m}, sweep_store_,
      run_id, robot_->runtime(), bus_, robot_->sweep_layer(), robot_->planning());
  if (robot_->backend().drivers().tilt) sweeps_->set_stage(robot_->sweep());
  Runtime& runtime = robot_->runtime();
  control_ = std::make_unique<ControlService>(
      runtime, *recorder_,
      ControlStages{robot_->mux(), robot_->navigate(), robot_->estimate(), robot_->write_base()},
      robot_->kinematics(), robot_->plugins(), config_.navigation);
  map_catalog_ = std::make_unique<MapCatalog>(maps_, zones_, runtime, robot_->map_listeners());
  mapping_ = std::make_unique<MappingService>(
      runtime, *recorder_, *map_catalog_,
      MappingStages{robot_->mapping(), robot_->estimate(), robot_->navigate()});
  localization_ = std::make_unique<LocalizationService>(runtime, *recorder_, robot_->estimate(),
                                                        robot_->plugins());
  run_archive_ = std::make_unique<RunArchive>(runs_, *recorder_, runtime);
  audit_ = std::make_unique<CommandAudit>(runtime, *recorder_);
  camera_ = std::make_unique<CameraService>(runtime, *recorder_, robot_->tracking(),
                                            robot_->follow(), robot_->navigate(),
                                            robot_->backend().drivers().pan_tilt.get());
  if (drivers::SimControl* sim = robot_->backend().sim_control()) {
    if (config_.sim.provide_map) {
      map_catalog_->ensure_named_map(sim->world_name(), sim->surveyed_map(),
                                     MapCatalog::Activation::kWhenNoneActive);
    }
    sim_ = std::make_unique<SimService>(
        *sim, runtime, *recorder_, *map_catalog_,
        ResetStages{robot_->mux(), robot_->navigate(), robot_->estimate(),
                    robot_->backend().drivers().tilt ? &robot_->sweep() : nullptr});
  }
  map_catalog_->activate_stored_now();
  runtime.run_posted();
  rest_ = std::make_unique<api::RestApi>(ports(), hub_,
                                         api::RestOptions{web_dir_of(config_), MOBOT_VERSION});
  http_ = std::make_unique<api::HttpServer>(io_, *rest_, hub_, ports(),
                                            tls_ ? &*tls_ : nullptr);
}

App::~App() { shut_down(); }

api::Ports App::ports() {
  return {*control_, *map_catalog_, *mapping_, *localization_, *run_archive_,
          *token_admin_, *sweeps_, *this, *camera_, *audit_, sim_.get()};
}

void App::ensure_admin_token() {
  const auto token = token_admin_->create_first_admin();
  if (!token) return;
  const std::filesystem::path file = admin_token_path(config_.server.data_dir);
  {
    std::ofstream out(file, std::ios::trunc);
    out << *token << "\n";
  }
  ::chmod(file.c_str(), S_IRUSR | S_IWUSR);
  spdlog::info("created the admin token in {}", file.string());
}

int App::run() {
  // Installed before the ready line: a SIGTERM right after it must stop the server cleanly, not
  // kill it with the default disposition.
  boost::asio::io_context signals_io;
  boost::asio::signal_set signals(signals_io, SIGINT, SIGTERM);
  int received = 0;
  signals.async_wait([&](boost::system::error_code, int signal) { received = signal; });

  const auto endpoint = http_->listen({config_.server.bind_address, config_.server.port});
  robot_->runtime().start(config_.sim.time_scale);
  wait_for_first_tick();
  const unsigned threads = std::max(2U, std::thread::hardware_concurrency());
  for (unsigned i = 0; i < threads; ++i) io_threads_.emplace_back([this] { io_.run(); });

  const std::string url = std::string(http_->secure() ? "https://" : "http://") +
                          endpoint.address().to_string() + ":" + std::to_string(endpoint.port());
  std::cout << "mobotd listening on " << url << std::endl;
  std::ifstream token_file(admin_token_path(config_.server.data_dir));
  std::string admin_token;
  if (token_file >> admin_token) {
    std::cout << "dashboard: " << url << "/?token=" << admin_token << std::endl;
  }

  signals_io.run();
  spdlog::info("signal {} received: stopping the robot and closing the run", received);
  shut_down();
  return 0;
}

void App::wait_for_first_tick() {
  // Requests are served from the first tick on: before it the published state has no pose from
  // the drivers, no sensors and no localization method. The loop's period bounds the wait.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (robot_->runtime().state()->robot.t_s <= 0.0 &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

void App::shut_down() {
  if (stopped_) return;
  stopped_ = true;
  robot_->runtime().stop();
  // The loop is stopped: nothing else touches the base now.
  robot_->write_base().stop_now();
  http_->stop();
  map_catalog_->stop();
  sweeps_->stop();  // records its last event: before the recorder stops
  hub_.close_all();
  recorder_->stop(unix_now_s());
  // Give sessions a moment to send their close frames, then stop the network threads.
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  io_.stop();
  for (auto& thread : io_threads_) thread.join();
  io_threads_.clear();
}

double App::uptime_s() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
}

std::string App::metrics_text() const {
  const auto state = robot_->runtime().state();
  std::string out;
  api::append_metric(out, "mobot_robot_time_seconds", "gauge", "Robot clock.", state->robot.t_s);
  api::append_metric(out, "mobot_collisions_total", "counter", "Collisions since start.",
                     static_cast<double>(robot_->safety().contacts()));
  api::append_metric(out, "mobot_estop", "gauge", "E-stop engaged (1) or not (0).",
                     state->robot.estop ? 1.0 : 0.0);
  api::append_metric(out, "mobot_navigating", "gauge", "A goal is active (1) or not (0).",
                     state->robot.mode == "navigating" ? 1.0 : 0.0);
  out += robot_->estimate().metrics_text();
  bool first = true;
  for (const auto& [name, sensor] : state->robot.sensors) {
    const std::string labels = "sensor=\"" + name + "\"";
    if (first) {
      api::append_metric(out, "mobot_sensor_rate_hz", "gauge", "Measured sensor rate.",
                         sensor.rate_hz, labels);
    } else {
      api::append_sample(out, "mobot_sensor_rate_hz", sensor.rate_hz, labels);
    }
    first = false;
  }
  out += device_metrics_text(robot_->backend().device_counters());
  out += robot_->runtime().metrics_text() + recorder_->metrics_text() + http_->metrics_text();
  api::append_metric(out, "mobot_uptime_seconds", "gauge", "Seconds since start.", uptime_s());
  return out;
}

}  // namespace mobot::server
