#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "db/database.h"

namespace mobot::db {

enum class Role { kViewer = 0, kOperator = 1, kAdmin = 2 };

struct TokenRecord {
  std::int64_t id = 0;
  Role role = Role::kViewer;
  std::string label;
  double created_unix_s = 0.0;
  bool revoked = false;
  // From this unix time (whole seconds) on the token no longer authenticates; none: until revoked.
  std::optional<std::int64_t> expires_unix_s;
};

// API tokens, stored only as hashes: a leaked database does not leak a usable token. Whether an
// expiry has passed is the caller's to judge (it has the clock); the store keeps the time.
class TokenStore {
 public:
  explicit TokenStore(Database& database) : database_(database), lookups_(database) {}
  // `lookups`: another connection to the same file, for find() alone. Every request checks its
  // token there, and in WAL mode a reader on its own connection never waits for a commit (the
  // recorder's fsync) that holds `database`.
  TokenStore(Database& database, Database& lookups) : database_(database), lookups_(lookups) {}

  std::int64_t add(const std::string& hash, Role role, const std::string& label,
                   double created_unix_s, std::optional<std::int64_t> expires_unix_s = {});
  // The live (not revoked) token with this hash, expired or not, as last committed by anyone.
  std::optional<TokenRecord> find(const std::string& hash) const;
  // The live token with this id, the same way.
  std::optional<TokenRecord> find_by_id(std::int64_t id) const;
  std::vector<TokenRecord> list() const;
  // False when no live token has this id.
  bool revoke(std::int64_t id);
  // Admin tokens neither revoked nor expired at `now_unix_s`.
  int count_admins(double now_unix_s) const;

 private:
  // The live token matching `condition` (one placeholder, bound by `bind`), on `lookups_`.
  std::optional<TokenRecord> find_live(const char* condition,
                                       const std::function<void(Statement&)>& bind) const;

  Database& database_;
  Database& lookups_;
};

}  // namespace mobot::db
