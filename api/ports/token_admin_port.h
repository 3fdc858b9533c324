#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mobot::api {

enum class Role { kViewer = 0, kOperator = 1, kAdmin = 2 };

struct TokenInfo {
  std::int64_t id = 0;
  Role role = Role::kViewer;
  std::string label;
  double created_unix_s = 0.0;
  bool revoked = false;
};

// Who a request comes from: the token's id and label (a person, or a service) and its role. The
// process's own admin token (--token) is id 0.
struct Caller {
  std::int64_t token_id = 0;
  Role role = Role::kViewer;
  std::string label;
};

// Who may do what: token checks for every request, token management for admins. Thread-safe.
class TokenAdminPort {
 public:
  virtual ~TokenAdminPort() = default;

  virtual std::optional<Caller> authenticate(std::string_view token) = 0;
  // Returns the id and the plain token, shown only once.
  virtual std::pair<std::int64_t, std::string> create_token(Role role,
                                                            const std::string& label) = 0;
  virtual std::vector<TokenInfo> list_tokens() const = 0;
  virtual bool revoke_token(std::int64_t id) = 0;
};

}  // namespace mobot::api
