#include "api/tls_context.h"

#include <openssl/err.h>
#include <openssl/ssl.h>

#include <string>

namespace mobot::api {
namespace {

// OpenSSL's reason for the last failure ("no start line", "key values mismatch"), its queue
// emptied so that the next call starts clean.
std::string openssl_reason(const boost::system::error_code& error) {
  std::string reason = error ? error.message() : std::string{};
  unsigned long code = 0;
  while ((code = ERR_get_error()) != 0) {
    char text[256];
    ERR_error_string_n(code, text, sizeof text);
    reason = text;
  }
  return reason.empty() ? "unknown OpenSSL error" : reason;
}

}  // namespace

boost::asio::ssl::context make_tls_server_context(const TlsFiles& files) {
  namespace ssl = boost::asio::ssl;
  ssl::context context(ssl::context::tls_server);
  boost::system::error_code error;
  context.set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 |
                          ssl::context::no_sslv3 | ssl::context::no_tlsv1 |
                          ssl::context::no_tlsv1_1 | ssl::context::single_dh_use,
                      error);
  if (error || SSL_CTX_set_min_proto_version(context.native_handle(), TLS1_2_VERSION) != 1) {
    throw TlsSetupError("cannot restrict TLS to 1.2 and later: " + openssl_reason(error));
  }
  context.use_certificate_chain_file(files.certificate_chain.string(), error);
  if (error) {
    throw TlsSetupError("cannot load the certificate chain " + files.certificate_chain.string() +
                        " (PEM): " + openssl_reason(error));
  }
  const auto mismatch = [&files](const std::string& reason) {
    return TlsSetupError("the private key " + files.private_key.string() +
                         " does not match the certificate in " +
                         files.certificate_chain.string() + ": " + reason);
  };
  context.use_private_key_file(files.private_key.string(), ssl::context::pem, error);
  if (error) {
    // OpenSSL checks the key against the certificate as it loads it.
    const std::string reason = openssl_reason(error);
    if (reason.find("mismatch") != std::string::npos) throw mismatch(reason);
    throw TlsSetupError("cannot load the private key " + files.private_key.string() +
                        " (PEM): " + reason);
  }
  if (SSL_CTX_check_private_key(context.native_handle()) != 1) throw mismatch(openssl_reason({}));
  return context;
}

}  // namespace mobot::api
