#include "server/token_command.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <vector>

#include "api/role_names.h"
#include "db/database.h"
#include "db/token_store.h"
#include "server/data_dir.h"
#include "server/services/token_admin.h"

namespace mobot::server {
namespace {

// UTC, to the second: the same instant whoever reads it and wherever the robot is.
std::string utc_time(double unix_s) {
  const auto seconds = static_cast<std::time_t>(std::floor(unix_s));
  std::tm parts{};
  ::gmtime_r(&seconds, &parts);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%d %H:%M:%SZ", &parts);
  return text;
}

void print_table(const std::vector<std::vector<std::string>>& rows, std::ostream& out) {
  std::vector<std::size_t> widths;
  for (const auto& row : rows) {
    widths.resize(std::max(widths.size(), row.size()));
    for (std::size_t i = 0; i < row.size(); ++i) widths[i] = std::max(widths[i], row[i].size());
  }
  for (const auto& row : rows) {
    std::string line;
    for (std::size_t i = 0; i < row.size(); ++i) {
      line += row[i];
      if (i + 1 < row.size()) line += std::string(widths[i] - row[i].size() + 2, ' ');
    }
    out << line << "\n";
  }
}

void list_tokens(const TokenAdmin& admin, std::ostream& out) {
  std::vector<std::vector<std::string>> rows{
      {"id", "role", "label", "created", "expires", "revoked"}};
  for (const api::TokenInfo& token : admin.list_tokens()) {
    rows.push_back({std::to_string(token.id), std::string(api::role_name(token.role)),
                    token.label.empty() ? "-" : token.label, utc_time(token.created_unix_s),
                    token.expires_unix_s ? utc_time(static_cast<double>(*token.expires_unix_s))
                                         : "never",
                    token.revoked ? "yes" : "no"});
  }
  print_table(rows, out);
}

}  // namespace

int run_token_command(const TokenCommand& command, const std::filesystem::path& data_dir,
                      std::ostream& out, std::ostream& err) {
  const std::filesystem::path store = store_path(data_dir);
  if (command.action == TokenCommand::Action::kCreate) {
    // The first token of an installation may come before the server's first start.
    std::filesystem::create_directories(data_dir);
  } else if (!std::filesystem::exists(store)) {
    err << "mobotd token: no store at " << store.string()
        << " (no mobotd has used this data dir yet)\n";
    return 1;
  }
  db::Database database = db::Database::open(store);
  db::TokenStore tokens(database);
  TokenAdmin admin(tokens, "");
  switch (command.action) {
    case TokenCommand::Action::kCreate: {
      const api::CreatedToken created =
          admin.create_token(command.role, command.label, command.lifetime_s);
      // stdout carries the token alone, so that a script can take it: `T=$(mobotd token create ...)`.
      out << created.token << std::endl;
      err << "token " << created.id << " (" << api::role_name(command.role) << ") created"
          << (created.expires_unix_s
                  ? ", expires " + utc_time(static_cast<double>(*created.expires_unix_s))
                  : std::string{})
          << "; it is not shown again\n";
      return 0;
    }
    case TokenCommand::Action::kList:
      list_tokens(admin, out);
      return 0;
    case TokenCommand::Action::kRevoke:
      if (!admin.revoke_token(command.id)) {
        err << "mobotd token: no live token with id " << command.id << "\n";
        return 1;
      }
      out << "token " << command.id << " revoked\n";
      return 0;
  }
  return 1;
}

}  // namespace mobot::server
