#include "server/token_auth.h"

#include <gtest/gtest.h>

#include <set>

namespace mobot::server {
namespace {

TEST(TokenAuth, HashIsSha256Hex) {
  EXPECT_EQ(hash_token("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST(TokenAuth, GeneratedTokensAreLongAndDistinct) {
  std::set<std::string> seen;
  for (int i = 0; i < 100; ++i) {
    const std::string token = generate_token();
    EXPECT_EQ(token.size(), 64U);
    EXPECT_TRUE(seen.insert(token).second);
  }
}

}  // namespace
}  // namespace mobot::server
