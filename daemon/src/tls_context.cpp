#include "garmcap/daemon/tls_context.h"

#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/ssl.h>
#include <openssl/x509.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

namespace garmcap::daemon {

namespace ssl = boost::asio::ssl;

namespace {

// SSLv2/3 and TLS 1.0/1.1 are off both ways; the protocol floor is set too, so a later OpenSSL
// default cannot lower it.
std::shared_ptr<ssl::context> baseContext(ssl::context::method method) {
  auto ctx = std::make_shared<ssl::context>(method);
  ctx->set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 |
                   ssl::context::no_sslv3 | ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1 |
                   ssl::context::single_dh_use);
  if (SSL_CTX_set_min_proto_version(ctx->native_handle(), TLS1_2_VERSION) != 1)
    throw TlsError("tls: cannot require TLS 1.2: " + takeOpensslError());
  return ctx;
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

File openPem(const std::string& file, const std::string& what) {
  if (file.empty())
    throw TlsError("tls: no " + what + " file given");
  File f(std::fopen(file.c_str(), "rb"));
  if (!f)
    throw TlsError(what + " " + file + ": cannot be read: " + std::strerror(errno));
  return f;
}

// An encrypted key would make OpenSSL prompt on the terminal; the service has none.
int noPassword(char*, int, int, void*) {
  return 0;
}

}  // namespace

std::string takeOpensslError() {
  unsigned long code = 0, last = 0;
  while ((code = ERR_get_error()) != 0)
    last = code;
  if (last == 0)
    return "";
  char text[256];
  ERR_error_string_n(last, text, sizeof text);
  return text;
}

std::shared_ptr<ssl::context> makeServerTlsContext(const std::string& certFile,
                                                   const std::string& keyFile) {
  auto ctx = baseContext(ssl::context::tls_server);
  openPem(certFile, "TLS certificate");
  ERR_clear_error();
  if (SSL_CTX_use_certificate_chain_file(ctx->native_handle(), certFile.c_str()) != 1)
    throw TlsError("TLS certificate " + certFile +
                   ": not a PEM certificate chain: " + takeOpensslError());
  File keyIn = openPem(keyFile, "TLS key");
  std::unique_ptr<EVP_PKEY, decltype(&EVP_PKEY_free)> key(
      PEM_read_PrivateKey(keyIn.get(), nullptr, noPassword, nullptr), &EVP_PKEY_free);
  if (!key)
    throw TlsError("TLS key " + keyFile +
                   ": not an unencrypted PEM private key: " + takeOpensslError());
  X509* cert = SSL_CTX_get0_certificate(ctx->native_handle());
  if (!cert || X509_check_private_key(cert, key.get()) != 1) {
    ERR_clear_error();
    throw TlsError("TLS key " + keyFile + ": does not match the certificate in " + certFile);
  }
  if (SSL_CTX_use_PrivateKey(ctx->native_handle(), key.get()) != 1)
    throw TlsError("TLS key " + keyFile + ": " + takeOpensslError());
  return ctx;
}

std::shared_ptr<ssl::context> makeClientTlsContext(const std::string& caFile) {
  auto ctx = baseContext(ssl::context::tls_client);
  ctx->set_verify_mode(ssl::verify_peer);
  boost::system::error_code ec;
  if (caFile.empty()) {
    ctx->set_default_verify_paths(ec);
    if (ec)
      throw TlsError("tls: the system's certificate store cannot be read: " + ec.message());
    return ctx;
  }
  openPem(caFile, "CA file");
  ERR_clear_error();
  if (SSL_CTX_load_verify_locations(ctx->native_handle(), caFile.c_str(), nullptr) != 1)
    throw TlsError("CA file " + caFile + ": no PEM certificate in it: " + takeOpensslError());
  return ctx;
}

}  // namespace garmcap::daemon
