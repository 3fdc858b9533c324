#pragma once

#include <filesystem>
#include <string>

namespace mobot::testing {

// A certificate and its key as PEM files, made by the test itself (no `openssl` command).
struct TestCertificate {
  std::filesystem::path cert_file;
  std::filesystem::path key_file;
};

// A self-signed server certificate for 127.0.0.1 (CN and subjectAltName IP:127.0.0.1) with a
// fresh EC P-256 key, valid from a minute ago for a day, written to DIR/NAME.crt and DIR/NAME.key.
// A client that trusts the certificate file and checks the address accepts the server. Throws
// std::runtime_error when OpenSSL refuses.
TestCertificate make_test_certificate(const std::filesystem::path& dir,
                                      const std::string& name = "server");

}  // namespace mobot::testing
