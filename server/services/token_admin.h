#pragma once

#include <functional>
#include <string>

#include "api/ports/token_admin_port.h"
#include "db/token_store.h"

namespace mobot::server {

// The TokenAdminPort: hashed tokens in the store, and one admin token that lives only as long as
// the process (--token, id 0). Every check reads the store: a token revoked or expired is refused
// from that moment, also when another process (`mobotd token revoke`) revoked it.
class TokenAdmin final : public api::TokenAdminPort {
 public:
  // Unix seconds now; a test's clock in tests.
  using WallClock = std::function<double()>;

  TokenAdmin(db::TokenStore& tokens, const std::string& process_admin_token);
  TokenAdmin(db::TokenStore& tokens, const std::string& process_admin_token, WallClock now);

  std::optional<api::Caller> authenticate(std::string_view token) override;
  api::CreatedToken create_token(api::Role role, const std::string& label,
                                 std::optional<std::int64_t> lifetime_s) override;
  std::vector<api::TokenInfo> list_tokens() const override;
  bool revoke_token(std::int64_t id) override;
  bool is_active(std::int64_t token_id) override;

  // The plain admin token made for the first start, when the store has no usable admin token.
  std::optional<std::string> create_first_admin();

 private:
  db::TokenStore& tokens_;
  std::string process_admin_hash_;
  WallClock now_;
};

}  // namespace mobot::server
