#pragma once

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

}  // namespace mobot::api
