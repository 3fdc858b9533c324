#pragma once

#include <span>
#include <string_view>

namespace mobot::db {

// The schema as a sequence of steps; step i brings PRAGMA user_version from i to i + 1. Steps are
// only ever appended: a database written by an older mobotd is upgraded in place on open.
std::span<const std::string_view> schema_migrations();

}  // namespace mobot::db
