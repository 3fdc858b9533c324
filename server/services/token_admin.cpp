#include "server/services/token_admin.h"

#include "server/wall_clock.h"

#include <chrono>

#include "server/token_auth.h"

namespace mobot::server {
TokenAdmin::TokenAdmin(db::TokenStore& tokens, const std::string& process_admin_token)
    : tokens_(tokens),
      process_admin_hash_(process_admin_token.empty() ? "" : hash_token(process_admin_token)) {}

std::optional<std::string> TokenAdmin::create_first_admin() {
  if (tokens_.count_admins() > 0) return std::nullopt;
  std::string token = generate_token();
  tokens_.add(hash_token(token), db::Role::kAdmin, "first start", unix_now_s());
  return token;
}

std::optional<api::Caller> TokenAdmin::authenticate(std::string_view token) {
  if (token.size() > 256) return std::nullopt;
  const std::string hash = hash_token(token);
  if (!process_admin_hash_.empty() && hash == process_admin_hash_) {
    return api::Caller{0, api::Role::kAdmin, "admin (--token)"};
  }
  {
    std::lock_guard lock(mutex_);
    if (auto it = caller_cache_.find(hash); it != caller_cache_.end()) return it->second;
  }
  const auto record = tokens_.find(hash);
  if (!record) return std::nullopt;
  const api::Caller caller{record->id, static_cast<api::Role>(static_cast<int>(record->role)),
                           record->label};
  std::lock_guard lock(mutex_);
  caller_cache_[hash] = caller;
  return caller;
}

std::pair<std::int64_t, std::string> TokenAdmin::create_token(api::Role role,
                                                              const std::string& label) {
  const std::string token = generate_token();
  const auto id = tokens_.add(hash_token(token), static_cast<db::Role>(static_cast<int>(role)),
                              label, unix_now_s());
  return {id, token};
}

std::vector<api::TokenInfo> TokenAdmin::list_tokens() const {
  std::vector<api::TokenInfo> out;
  for (const auto& token : tokens_.list()) {
    out.push_back({token.id, static_cast<api::Role>(static_cast<int>(token.role)), token.label,
                   token.created_unix_s, token.revoked});
  }
  return out;
}

bool TokenAdmin::revoke_token(std::int64_t id) {
  if (!tokens_.revoke(id)) return false;
  // A revoked token must stop working at once, not when its cache entry ages out.
  std::lock_guard lock(mutex_);
  caller_cache_.clear();
  return true;
}

}  // namespace mobot::server
