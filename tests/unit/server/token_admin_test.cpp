// Token checks (server/services/token_admin.cpp): expiry against the wall clock, and revocation,
// also by another process on the same store, take effect for the very next check.
#include "server/services/token_admin.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

namespace mobot::server {
namespace {

class TokenAdminTest : public ::testing::Test {
 protected:
  double now_ = 1'700'000'000.25;
  db::Database database_ = db::Database::open_in_memory();
  db::TokenStore store_{database_};
  TokenAdmin admin_{store_, "process-token", [this] { return now_; }};
};

TEST_F(TokenAdminTest, ATokenWithALifetimeWorksUntilItsExpirySecondAndNotFrom) {
  const api::CreatedToken made = admin_.create_token(api::Role::kOperator, "kim", 60);
  ASSERT_TRUE(made.expires_unix_s.has_value());
  EXPECT_EQ(*made.expires_unix_s, 1'700'000'061) << "whole seconds, at least the lifetime";
  const auto caller = admin_.authenticate(made.token);
  ASSERT_TRUE(caller.has_value());
  EXPECT_EQ(caller->label, "kim");
  EXPECT_EQ(caller->role, api::Role::kOperator);
  now_ = 1'700'000'060.999;
  EXPECT_TRUE(admin_.authenticate(made.token).has_value());
  now_ = 1'700'000'061.0;
  EXPECT_FALSE(admin_.authenticate(made.token).has_value()) << "expired: refused at once";
  const auto listed = admin_.list_tokens();
  ASSERT_EQ(listed.size(), 1U);
  EXPECT_EQ(listed[0].expires_unix_s, 1'700'000'061);
  EXPECT_FALSE(listed[0].revoked);
}

TEST_F(TokenAdminTest, ATokenWithoutALifetimeLastsUntilRevoked) {
  const api::CreatedToken made = admin_.create_token(api::Role::kViewer, "lee", std::nullopt);
  EXPECT_FALSE(made.expires_unix_s.has_value());
  now_ += 10.0 * 365 * 24 * 3600;
  EXPECT_TRUE(admin_.authenticate(made.token).has_value());
  EXPECT_TRUE(admin_.revoke_token(made.id));
  EXPECT_FALSE(admin_.authenticate(made.token).has_value());
  EXPECT_FALSE(admin_.revoke_token(made.id));
}

TEST_F(TokenAdminTest, TheProcessTokenIsAdminAndOverlongTokensNeverMatch) {
  const auto caller = admin_.authenticate("process-token");
  ASSERT_TRUE(caller.has_value());
  EXPECT_EQ(caller->token_id, 0);
  EXPECT_EQ(caller->role, api::Role::kAdmin);
  EXPECT_FALSE(admin_.authenticate(std::string(257, 'a')).has_value());
  EXPECT_FALSE(admin_.authenticate("").has_value());
}

TEST_F(TokenAdminTest, TheFirstAdminIsMadeAgainWhenEveryAdminTokenHasExpired) {
  const api::CreatedToken made = admin_.create_token(api::Role::kAdmin, "temp", 60);
  EXPECT_FALSE(admin_.create_first_admin().has_value()) << "a live admin token exists";
  now_ += 61;
  const auto first = admin_.create_first_admin();
  ASSERT_TRUE(first.has_value()) << "nobody could administer the robot any more";
  EXPECT_EQ(admin_.authenticate(*first)->role, api::Role::kAdmin);
  EXPECT_FALSE(admin_.authenticate(made.token).has_value());
}

// `mobotd token revoke` is another process with its own connection to the store.
TEST(TokenAdminStore, ARevocationByAnotherConnectionIsSeenByTheNextCheck) {
  const auto file = std::filesystem::temp_directory_path() /
                    ("mobot_token_admin_" + std::to_string(::getpid()) + ".sqlite");
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(file.string() + suffix);
  {
    db::Database server_db = db::Database::open(file);
    db::TokenStore server_store(server_db);
    TokenAdmin server(server_store, "");
    const api::CreatedToken made = server.create_token(api::Role::kViewer, "max", std::nullopt);
    ASSERT_TRUE(server.authenticate(made.token).has_value());
    {
      db::Database tool_db = db::Database::open(file);
      db::TokenStore tool_store(tool_db);
      EXPECT_TRUE(TokenAdmin(tool_store, "").revoke_token(made.id));
    }
    EXPECT_FALSE(server.authenticate(made.token).has_value());
  }
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(file.string() + suffix);
}

}  // namespace
}  // namespace mobot::server
