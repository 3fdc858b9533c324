#pragma once

#include <filesystem>

namespace mobot::server {

// What lives in the data dir (server.data_dir, --data-dir): mobotd and `mobotd token` find the
// store at the same place.
inline std::filesystem::path store_path(const std::filesystem::path& data_dir) {
  return data_dir / "mobot.sqlite";
}
// The first start's admin token, readable by its owner only.
inline std::filesystem::path admin_token_path(const std::filesystem::path& data_dir) {
  return data_dir / "admin.token";
}

}  // namespace mobot::server
