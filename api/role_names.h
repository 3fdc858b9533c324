#pragma once

#include <optional>
#include <string_view>

#include "api/ports/token_admin_port.h"

namespace mobot::api {

// A role as the API spells it: "viewer", "operator", "admin".
constexpr std::string_view role_name(Role role) {
  switch (role) {
    case Role::kOperator:
      return "operator";
    case Role::kAdmin:
      return "admin";
    case Role::kViewer:
      break;
  }
  return "viewer";
}

// The role a name spells, or nullopt for any other text.
constexpr std::optional<Role> role_from_name(std::string_view name) {
  for (const Role role : {Role::kViewer, Role::kOperator, Role::kAdmin}) {
    if (name == role_name(role)) return role;
  }
  return std::nullopt;
}

}  // namespace mobot::api
