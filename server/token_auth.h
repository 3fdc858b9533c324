#pragma once

#include <string>
#include <string_view>

namespace mobot::server {

// Tokens are stored only as SHA-256 hashes; the plain token exists in the admin.token file and in
// the clients that hold it.
std::string hash_token(std::string_view token);
// 32 random bytes from the OS CSPRNG, hex-encoded.
std::string generate_token();

}  // namespace mobot::server
