#include "db/token_store.h"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "db/migrations.h"

namespace mobot::db {
namespace {

class TokenStoreTest : public ::testing::Test {
 protected:
  Database database_ = Database::open_in_memory();
  TokenStore tokens_{database_};
};

TEST_F(TokenStoreTest, FindsTheIdRoleAndLabelOfALiveToken) {
  const auto id = tokens_.add("h1", Role::kOperator, "ops", 1.0);
  const auto found = tokens_.find("h1");
  ASSERT_TRUE(found.has_value());
  EXPECT_EQ(found->id, id);
  EXPECT_EQ(found->role, Role::kOperator);
  EXPECT_EQ(found->label, "ops");
  EXPECT_FALSE(tokens_.find("h2"));
}

TEST_F(TokenStoreTest, ARevokedTokenNoLongerAuthenticates) {
  const auto id = tokens_.add("h1", Role::kAdmin, "", 1.0);
  EXPECT_EQ(tokens_.count_admins(2.0), 1);
  EXPECT_TRUE(tokens_.revoke(id));
  EXPECT_FALSE(tokens_.find("h1"));
  EXPECT_EQ(tokens_.count_admins(2.0), 0);
  EXPECT_FALSE(tokens_.revoke(id));
  EXPECT_FALSE(tokens_.revoke(12345));
  ASSERT_EQ(tokens_.list().size(), 1U);
  EXPECT_TRUE(tokens_.list()[0].revoked);
}

TEST_F(TokenStoreTest, AHashIsStoredOnce) {
  tokens_.add("same", Role::kViewer, "", 1.0);
  EXPECT_THROW(tokens_.add("same", Role::kAdmin, "", 2.0), DbError);
  ASSERT_TRUE(tokens_.find("same").has_value());
  EXPECT_EQ(tokens_.find("same")->role, Role::kViewer);
}

TEST_F(TokenStoreTest, KeepsTheExpiryAndCountsOnlyAdminsThatHaveNotExpired) {
  const auto lasting = tokens_.add("h1", Role::kAdmin, "lasting", 1.0);
  const auto lapsing = tokens_.add("h2", Role::kAdmin, "lapsing", 1.0, 1000);
  EXPECT_FALSE(tokens_.find("h1")->expires_unix_s.has_value());
  ASSERT_TRUE(tokens_.find("h2").has_value()) << "an expired token is still found: the caller judges";
  EXPECT_EQ(tokens_.find("h2")->expires_unix_s, 1000);
  EXPECT_EQ(tokens_.count_admins(999.0), 2);
  EXPECT_EQ(tokens_.count_admins(1000.0), 1) << "expired at its expiry second";
  const auto listed = tokens_.list();
  ASSERT_EQ(listed.size(), 2U);
  EXPECT_EQ(listed[0].id, lasting);
  EXPECT_FALSE(listed[0].expires_unix_s.has_value());
  EXPECT_EQ(listed[1].id, lapsing);
  EXPECT_EQ(listed[1].expires_unix_s, 1000);
}

// mobotd checks tokens on a connection of their own: a check goes through while another unit of
// work holds the main connection (the recorder's commit), and sees what was committed last.
TEST(TokenStoreLookups, AreNotHeldUpByAWriteOnTheMainConnection) {
  const auto file = std::filesystem::temp_directory_path() /
                    ("mobot_token_lookups_" + std::to_string(::getpid()) + ".sqlite");
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(file.string() + suffix);
  {
    Database main = Database::open(file);
    Database lookups = Database::open(file);
    TokenStore tokens(main, lookups);
    const auto id = tokens.add("h1", Role::kViewer, "nell", 1.0);
    ASSERT_TRUE(tokens.find("h1").has_value());
    main.write([&](const Connection& tx) {
      tx.exec("INSERT INTO runs (name, started_unix_s) VALUES ('busy', 1)");
      // On the main connection this would wait for the write that is holding it: forever.
      const auto found = tokens.find("h1");
      ASSERT_TRUE(found.has_value());
      EXPECT_EQ(found->label, "nell");
    });
    EXPECT_TRUE(tokens.revoke(id));
    EXPECT_FALSE(tokens.find("h1").has_value()) << "the revocation is seen at once";
  }
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(file.string() + suffix);
}

// A store written by a mobotd from before token expiry (schema 3) keeps its tokens, which never
// expire.
TEST(TokenStoreMigration, TokensOfAnOlderSchemaKeepWorkingWithoutAnExpiry) {
  const auto file = std::filesystem::temp_directory_path() /
                    ("mobot_token_migration_" + std::to_string(::getpid()) + ".sqlite");
  std::filesystem::remove(file);
  {
    sqlite3* raw = nullptr;
    ASSERT_EQ(sqlite3_open(file.c_str(), &raw), SQLITE_OK);
    std::string script;
    for (std::size_t step = 0; step < 3; ++step) script += std::string(schema_migrations()[step]);
    script +=
        "INSERT INTO tokens (hash, role, label, created_unix_s) VALUES ('old', 2, 'first', 5);"
        "PRAGMA user_version = 3;";
    EXPECT_EQ(sqlite3_exec(raw, script.c_str(), nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(raw);
  }
  {
    Database database = Database::open(file);
    EXPECT_EQ(database.schema_version(), static_cast<int>(schema_migrations().size()));
    TokenStore tokens(database);
    const auto found = tokens.find("old");
    ASSERT_TRUE(found.has_value());
    EXPECT_EQ(found->label, "first");
    EXPECT_FALSE(found->expires_unix_s.has_value());
    EXPECT_EQ(tokens.count_admins(1e10), 1);
  }
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(file.string() + suffix);
}

}  // namespace
}  // namespace mobot::db
