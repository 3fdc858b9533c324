#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mobot::api {

enum class Role { kViewer = 0, kOperator = 1, kAdmin = 2 };

// How long a token may be made to last, when it is given a lifetime at all: a minute at least (a
// shorter one would lapse before a person could paste it), a year at most.
inline constexpr std::int64_t kMinTokenLifetime_s = 60;
inline constexpr std::int64_t kMaxTokenLifetime_s = 365 * 24 * 3600;
inline constexpr std::size_t kMaxTokenLabelChars = 128;

struct TokenInfo {
  std::int64_t id = 0;
  Role role = Role::kViewer;
  std::string label;
  double created_unix_s = 0.0;
  bool revoked = false;
  std::optional<std::int64_t> expires_unix_s;  // none: lasts until revoked
};

// A token just made: the plain token exists only here, shown once.
struct CreatedToken {
  std::int64_t id = 0;
  std::string token;
  std::optional<std::int64_t> expires_unix_s;
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

  // Who holds `token`; nullopt for an unknown, revoked or expired one, from the moment it is so.
  virtual std::optional<Caller> authenticate(std::string_view token) = 0;
  // `lifetime_s` (within the limits above, checked by the caller): the token expires that long
  // after now; none: it lasts until revoked.
  virtual CreatedToken create_token(Role role, const std::string& label,
                                    std::optional<std::int64_t> lifetime_s) = 0;
  virtual std::vector<TokenInfo> list_tokens() const = 0;
  virtual bool revoke_token(std::int64_t id) = 0;
  // Whether the token with this id still authenticates (neither revoked nor expired): what a
  // connection opened with it checks to stay open. The process's own token (0) always does.
  virtual bool is_active(std::int64_t token_id) = 0;
};

}  // namespace mobot::api
