#pragma once

#include <mutex>
#include <string>
#include <unordered_map>

#include "api/ports/token_admin_port.h"
#include "db/token_store.h"

namespace mobot::server {

// The TokenAdminPort: hashed tokens in the store, a cache of who they are, and one admin token
// that lives only as long as the process (--token, id 0).
class TokenAdmin final : public api::TokenAdminPort {
 public:
  TokenAdmin(db::TokenStore& tokens, const std::string& process_admin_token);

  std::optional<api::Caller> authenticate(std::string_view token) override;
  std::pair<std::int64_t, std::string> create_token(api::Role role,
                                                    const std::string& label) override;
  std::vector<api::TokenInfo> list_tokens() const override;
  bool revoke_token(std::int64_t id) override;

  // The plain admin token made for the first start, when the store has no admin yet.
  std::optional<std::string> create_first_admin();

 private:
  db::TokenStore& tokens_;
  std::string process_admin_hash_;
  std::mutex mutex_;
  std::unordered_map<std::string, api::Caller> caller_cache_;  // token hash -> who
};

}  // namespace mobot::server
