// mobotd: the mobot robot server. See README.md and docs/api.md for the flags and the API.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <sys/resource.h>

#include <algorithm>
#include <filesystem>
#include <iostream>

#include "api/role_names.h"
#include "drivers/backend_factory.h"
#include "server/app.h"
#include "server/config.h"
#include "server/token_command.h"

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
  std::string tls_cert;
  std::string tls_key;
};

// `mobotd token ...`: what to do and where the store is (found as the server finds it).
struct TokenFlags {
  std::string config_file;
  std::string data_dir;
  std::string role;
  std::string label;
  std::int64_t lifetime_s = 0;
  std::int64_t id = 0;
  mobot::server::TokenCommand::Action action = mobot::server::TokenCommand::Action::kList;
};

// Every connection is a descriptor, and the default soft limit (1024) is below what the server
// keeps open (api/http_server.h kMaxConnections) plus its devices and the store: raised as far as
// the hard limit allows, at most 65536.
void raise_descriptor_limit() {
  rlimit limit{};
  if (::getrlimit(RLIMIT_NOFILE, &limit) != 0) return;
  const rlim_t wanted = std::min<rlim_t>(limit.rlim_max, 65536);
  if (limit.rlim_cur >= wanted) return;
  limit.rlim_cur = wanted;
  if (::setrlimit(RLIMIT_NOFILE, &limit) != 0) {
    spdlog::warn("could not raise the open-file limit to {}", static_cast<unsigned long>(wanted));
  }
}

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
  if (!flags.tls_cert.empty()) config.server.tls_cert = flags.tls_cert;
  if (!flags.tls_key.empty()) config.server.tls_key = flags.tls_key;
  mobot::server::validate_config(config);
  return config;
}

void add_token_subcommand(CLI::App& cli, TokenFlags& flags) {
  using mobot::server::TokenCommand;
  CLI::App* token = cli.add_subcommand(
      "token", "make, list and revoke API tokens in the store (also while mobotd runs)");
  token->require_subcommand(1);
  token->add_option("--config", flags.config_file,
                    "YAML config file whose server.data_dir holds the store")
      ->check(CLI::ExistingFile);
  token->add_option("--data-dir", flags.data_dir, "where the SQLite store lives (default ./var)");

  CLI::App* create = token->add_subcommand(
      "create", "make a token and print it, alone, on stdout (it is not shown again)");
  create->fallthrough();
  create->add_option("--label", flags.label, "who or what holds it (1..128 characters)")
      ->required()
      ->check(CLI::Validator(
          [](const std::string& label) {
            return label.empty() || label.size() > mobot::api::kMaxTokenLabelChars
                       ? std::string("a label has 1 to 128 characters")
                       : std::string{};
          },
          "LABEL"));
  create->add_option("--role", flags.role, "viewer, operator or admin")
      ->required()
      ->check(CLI::IsMember({"viewer", "operator", "admin"}));
  create->add_option("--expires-in-s", flags.lifetime_s, "lifetime in seconds (60..31536000)")
      ->check(CLI::Range(mobot::api::kMinTokenLifetime_s, mobot::api::kMaxTokenLifetime_s));
  create->callback([&flags] { flags.action = TokenCommand::Action::kCreate; });

  CLI::App* list = token->add_subcommand(
      "list", "every token: id, role, label, created, expires, revoked (never the token)");
  list->fallthrough();
  list->callback([&flags] { flags.action = TokenCommand::Action::kList; });

  CLI::App* revoke = token->add_subcommand("revoke", "revoke a token: refused from now on");
  revoke->fallthrough();
  revoke->add_option("id", flags.id, "the token's id (mobotd token list)")
      ->required()
      ->check(CLI::PositiveNumber);
  revoke->callback([&flags] { flags.action = TokenCommand::Action::kRevoke; });
}

int run_token(const TokenFlags& flags) {
  try {
    Flags server_flags;
    server_flags.config_file = flags.config_file;
    server_flags.data_dir = flags.data_dir;
    const mobot::server::Config config = make_config(server_flags);
    mobot::server::TokenCommand command;
    command.action = flags.action;
    if (const auto role = mobot::api::role_from_name(flags.role)) command.role = *role;
    command.label = flags.label;
    if (flags.lifetime_s > 0) command.lifetime_s = flags.lifetime_s;
    command.id = flags.id;
    return mobot::server::run_token_command(command, config.server.data_dir, std::cout, std::cerr);
  } catch (const mobot::server::ConfigError& error) {
    std::cerr << "mobotd token: config: " << error.what() << "\n";
    return 2;
  } catch (const std::exception& error) {
    std::cerr << "mobotd token: " << error.what() << "\n";
    return 1;
  }
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
  cli.add_option("--tls-cert", flags.tls_cert,
                 "PEM certificate chain: serve https and wss only (with --tls-key)");
  cli.add_option("--tls-key", flags.tls_key, "PEM private key of --tls-cert");
  TokenFlags token_flags;
  add_token_subcommand(cli, token_flags);
  CLI11_PARSE(cli, argc, argv);
  if (cli.got_subcommand("token")) {
    // `mobotd --config FILE token list` finds the store as `mobotd token list --config FILE` does.
    if (token_flags.config_file.empty()) token_flags.config_file = flags.config_file;
    if (token_flags.data_dir.empty()) token_flags.data_dir = flags.data_dir;
    return run_token(token_flags);
  }

  // stdout carries only the ready line and the dashboard URL; logs go to stderr.
  auto logger = spdlog::stderr_color_mt("mobotd");
  spdlog::set_default_logger(logger);
  spdlog::set_level(spdlog::level::from_str(flags.log_level));
  raise_descriptor_limit();

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
