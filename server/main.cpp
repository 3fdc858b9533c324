// mobotd: the mobot robot server. See README.md and docs/api.md for the flags and the API.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>

#include "drivers/backend_factory.h"
#include "server/app.h"
#include "server/config.h"

namespace {

struct Flags {
  std::string config_file;
  std::string backend;
  std::string world;
  std::string bind_address;
  int port = -1;
  std::string data_dir;
  double time_scale = 0.0;
  std::int64_t seed = -1;
  std::string token;
  std::string run_name;
  std::string log_level = "info";
};

mobot::server::Config make_config(const Flags& flags) {
  using mobot::server::Config;
  std::filesystem::path file = flags.config_file;
  if (file.empty() && std::filesystem::exists(MOBOT_DEFAULT_CONFIG)) file = MOBOT_DEFAULT_CONFIG;
  Config config = file.empty() ? Config{} : mobot::server::load_config(file);
  if (!flags.backend.empty()) config.backend = flags.backend;
  if (!flags.world.empty()) config.sim.world = flags.world;
  if (!flags.bind_address.empty()) config.server.bind_address = flags.bind_address;
  if (flags.port >= 0) config.server.port = static_cast<std::uint16_t>(flags.port);
  if (!flags.data_dir.empty()) config.server.data_dir = flags.data_dir;
  if (flags.time_scale > 0.0) config.sim.time_scale = flags.time_scale;
  if (flags.seed >= 0) config.sim.seed = static_cast<std::uint64_t>(flags.seed);
  if (!flags.token.empty()) config.extra_admin_token = flags.token;
  if (!flags.run_name.empty()) config.run_name = flags.run_name;
  mobot::server::validate_config(config);
  return config;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"mobotd: runs a mobile robot (or its simulation) and serves it to the web"};
  Flags flags;
  cli.add_option("--config", flags.config_file,
                 "YAML config file (default deploy/config/default.yaml)")
      ->check(CLI::ExistingFile);
  cli.add_option("--backend", flags.backend, "sim or hardware")
      ->check(CLI::IsMember({"sim", "hardware"}));
  cli.add_option("--world", flags.world, "built-in world name or a world.yaml path (sim)");
  cli.add_option("--bind", flags.bind_address, "address to listen on (default 127.0.0.1)");
  cli.add_option("--port", flags.port, "port, 0 for an ephemeral one (default 8080)")
      ->check(CLI::Range(0, 65535));
  cli.add_option("--data-dir", flags.data_dir, "where the SQLite store lives (default ./var)");
  cli.add_option("--time-scale", flags.time_scale, "simulated seconds per wall second (0.1..100)")
      ->check(CLI::Range(0.1, 100.0));
  cli.add_option("--seed", flags.seed, "simulator seed")->check(CLI::NonNegativeNumber);
  cli.add_option("--token", flags.token, "an extra admin token valid for this process");
  cli.add_option("--run-name", flags.run_name, "name of the run recorded for this process");
  cli.add_option("--log-level", flags.log_level, "trace, debug, info, warn, error")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error"}));
  CLI11_PARSE(cli, argc, argv);

  // stdout carries only the ready line and the dashboard URL; logs go to stderr.
  auto logger = spdlog::stderr_color_mt("mobotd");
  spdlog::set_default_logger(logger);
  spdlog::set_level(spdlog::level::from_str(flags.log_level));

  try {
    mobot::server::App app(make_config(flags));
    return app.run();
  } catch (const mobot::server::ConfigError& error) {
    spdlog::error("config: {}", error.what());
    return 2;
  } catch (const mobot::drivers::BackendError& error) {
    spdlog::error("{}", error.what());
    return 2;
  } catch (const std::exception& error) {
    spdlog::error("mobotd cannot start: {}", error.what());
    return 1;
  }
}
