#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>

#include "api/ports/token_admin_port.h"

namespace mobot::server {

// `mobotd token create|list|revoke`: token administration on the store itself, for the people who
// run the robot (the first admin token of an installation, a token for a colleague) without a
// running server or an admin token. It opens the data dir's SQLite store as mobotd does (WAL, a
// busy timeout), so it works while a mobotd serves from the same store, which refuses a token
// revoked here from its next request on.
struct TokenCommand {
  enum class Action { kCreate, kList, kRevoke };
  Action action = Action::kList;
  api::Role role = api::Role::kViewer;                   // create
  std::string label;                                     // create
  std::optional<std::int64_t> lifetime_s;                // create: none lasts until revoked
  std::int64_t id = 0;                                   // revoke
};

// Carries out `command` on the store in `data_dir`. create prints the new token on `out` and
// nothing else; list prints a table that never holds a secret; revoke confirms on `out`. Problems
// go to `err`. Returns the process's exit code: 0 done, 1 refused (unknown id, no store).
int run_token_command(const TokenCommand& command, const std::filesystem::path& data_dir,
                      std::ostream& out, std::ostream& err);

}  // namespace mobot::server
