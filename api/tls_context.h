#pragma once

#include <filesystem>
#include <stdexcept>

#include <boost/asio/ssl/context.hpp>

namespace mobot::api {

// The PEM files a TLS server is made of: the certificate chain (the server's own certificate
// first, then the intermediates) and its private key.
struct TlsFiles {
  std::filesystem::path certificate_chain;
  std::filesystem::path private_key;
};

// A TLS file that does not load, or a key that is not the certificate's; the message names the
// file and what is wrong with it.
class TlsSetupError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The server side of TLS 1.2 and 1.3 (nothing older) with the certificate and key of `files`,
// OpenSSL's default cipher suites otherwise. Throws TlsSetupError.
boost::asio::ssl::context make_tls_server_context(const TlsFiles& files);

}  // namespace mobot::api
