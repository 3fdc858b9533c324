#include "db/token_store.h"

namespace mobot::db {
namespace {

std::optional<std::int64_t> optional_int64(const Statement& row, int column) {
  if (row.column_is_null(column)) return std::nullopt;
  return row.column_int64(column);
}

}  // namespace

std::int64_t TokenStore::add(const std::string& hash, Role role, const std::string& label,
                             double created_unix_s, std::optional<std::int64_t> expires_unix_s) {
  return database_.write([&](const Connection& tx) {
    Statement insert = tx.prepare(
        "INSERT INTO tokens (hash, role, label, created_unix_s, expires_at) "
        "VALUES (?, ?, ?, ?, ?)");
    insert.bind(1, hash).bind(2, static_cast<int>(role)).bind(3, label).bind(4, created_unix_s);
    // An unbound parameter is NULL: a token without an expiry.
    if (expires_unix_s) insert.bind(5, *expires_unix_s);
    insert.run();
    return tx.last_insert_id();
  });
}

std::optional<TokenRecord> TokenStore::find(const std::string& hash) const {
  return find_live("hash = ?", [&](Statement& row) { row.bind(1, hash); });
}

std::optional<TokenRecord> TokenStore::find_by_id(std::int64_t id) const {
  return find_live("id = ?", [&](Statement& row) { row.bind(1, id); });
}

std::optional<TokenRecord> TokenStore::find_live(
    const char* condition, const std::function<void(Statement&)>& bind) const {
  return lookups_.read([&](const Connection& connection) -> std::optional<TokenRecord> {
    Statement row = connection.prepare(
        std::string("SELECT id, role, label, created_unix_s, expires_at FROM tokens WHERE ") +
        condition + " AND revoked = 0");
    bind(row);
    if (!row.step()) return std::nullopt;
    return TokenRecord{row.column_int64(0),  static_cast<Role>(row.column_int64(1)),
                       row.column_text(2),   row.column_double(3),
                       false,                optional_int64(row, 4)};
  });
}

std::vector<TokenRecord> TokenStore::list() const {
  return database_.read([](const Connection& connection) {
    Statement rows = connection.prepare(
        "SELECT id, role, label, created_unix_s, revoked, expires_at FROM tokens ORDER BY id");
    std::vector<TokenRecord> out;
    while (rows.step()) {
      out.push_back({rows.column_int64(0), static_cast<Role>(rows.column_int64(1)),
                     rows.column_text(2), rows.column_double(3), rows.column_int64(4) != 0,
                     optional_int64(rows, 5)});
    }
    return out;
  });
}

bool TokenStore::revoke(std::int64_t id) {
  return database_.write([id](const Connection& tx) {
    tx.prepare("UPDATE tokens SET revoked = 1 WHERE id = ? AND revoked = 0").bind(1, id).run();
    return tx.changes() > 0;
  });
}

int TokenStore::count_admins(double now_unix_s) const {
  return database_.read([now_unix_s](const Connection& connection) {
    Statement row = connection.prepare(
        "SELECT COUNT(*) FROM tokens WHERE role = ? AND revoked = 0 "
        "AND (expires_at IS NULL OR expires_at > ?)");
    row.bind(1, static_cast<int>(Role::kAdmin)).bind(2, now_unix_s);
    row.step();
    return static_cast<int>(row.column_int64(0));
  });
}

}  // namespace mobot::db
