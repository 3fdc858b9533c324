#include "server/services/token_admin.h"

#include <cmath>

#include "server/token_auth.h"
#include "server/wall_clock.h"

namespace mobot::server {
namespace {

// A token longer than this is never valid: hashing megabytes per request costs, and no token we
// make is that long.
constexpr std::size_t kMaxTokenChars = 256;

}  // namespace

TokenAdmin::TokenAdmin(db::TokenStore& tokens, const std::string& process_admin_token)
    : TokenAdmin(tokens, process_admin_token, unix_now_s) {}

TokenAdmin::TokenAdmin(db::TokenStore& tokens, const std::string& process_admin_token,
                       WallClock now)
    : tokens_(tokens),
      process_admin_hash_(process_admin_token.empty() ? "" : hash_token(process_admin_token)),
      now_(std::move(now)) {}

std::optional<std::string> TokenAdmin::create_first_admin() {
  if (tokens_.count_admins(now_()) > 0) return std::nullopt;
  std::string token = generate_token();
  tokens_.add(hash_token(token), db::Role::kAdmin, "first start", now_());
  return token;
}

std::optional<api::Caller> TokenAdmin::authenticate(std::string_view token) {
  if (token.size() > kMaxTokenChars) return std::nullopt;
  const std::string hash = hash_token(token);
  if (!process_admin_hash_.empty() && hash == process_admin_hash_) {
    return api::Caller{0, api::Role::kAdmin, "admin (--token)"};
  }
  const auto record = tokens_.find(hash);
  if (!record) return std::nullopt;
  if (record->expires_unix_s && now_() >= static_cast<double>(*record->expires_unix_s)) {
    return std::nullopt;
  }
  return api::Caller{record->id, static_cast<api::Role>(static_cast<int>(record->role)),
                     record->label};
}

api::CreatedToken TokenAdmin::create_token(api::Role role, const std::string& label,
                                           std::optional<std::int64_t> lifetime_s) {
  const double now = now_();
  std::optional<std::int64_t> expires;
  // Whole seconds, rounded up: the token lasts at least the lifetime asked for.
  if (lifetime_s) expires = static_cast<std::int64_t>(std::ceil(now)) + *lifetime_s;
  std::string token = generate_token();
  const auto id = tokens_.add(hash_token(token), static_cast<db::Role>(static_cast<int>(role)),
                              label, now, expires);
  return {id, std::move(token), expires};
}

std::vector<api::TokenInfo> TokenAdmin::list_tokens() const {
  std::vector<api::TokenInfo> out;
  for (const auto& token : tokens_.list()) {
    out.push_back({token.id, static_cast<api::Role>(static_cast<int>(token.role)), token.label,
                   token.created_unix_s, token.revoked, token.expires_unix_s});
  }
  return out;
}

bool TokenAdmin::revoke_token(std::int64_t id) { return tokens_.revoke(id); }

bool TokenAdmin::is_active(std::int64_t token_id) {
  if (token_id == 0) return !process_admin_hash_.empty();
  const auto record = tokens_.find_by_id(token_id);
  return record &&
         !(record->expires_unix_s && now_() >= static_cast<double>(*record->expires_unix_s));
}

}  // namespace mobot::server
