#include "db/token_store.h"

#include <gtest/gtest.h>

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
  EXPECT_EQ(tokens_.count_admins(), 1);
  EXPECT_TRUE(tokens_.revoke(id));
  EXPECT_FALSE(tokens_.find("h1"));
  EXPECT_EQ(tokens_.count_admins(), 0);
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

}  // namespace
}  // namespace mobot::db
