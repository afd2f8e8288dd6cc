#pragma once
// TLS contexts for the HTTP layer (Boost.Asio's SSL stream on OpenSSL 3): the hub's server side
// (a certificate chain and its key) and the station pusher's client side (the hub's CA, or the
// system store). Both refuse anything older than TLS 1.2 and keep OpenSSL's default ciphers.
// Errors name the file and what is wrong with it.

#include <boost/asio/ssl/context.hpp>
#include <memory>
#include <stdexcept>
#include <string>

namespace garmcap::daemon {

class TlsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A server context from PEM files: `certFile` holds the certificate, then any intermediates;
/// `keyFile` its private key (not encrypted: the service starts unattended). Throws TlsError
/// naming the file: missing or unreadable, not PEM, or a key that does not match the
/// certificate.
std::shared_ptr<boost::asio::ssl::context> makeServerTlsContext(const std::string& certFile,
                                                                const std::string& keyFile);

/// A client context that verifies the peer's chain against the PEM certificates in `caFile`,
/// or against the system's store when `caFile` is empty. The host name is checked per
/// connection (ssl::host_name_verification). Throws TlsError naming the file.
std::shared_ptr<boost::asio::ssl::context> makeClientTlsContext(const std::string& caFile);

/// The newest OpenSSL error of this thread as text ("" when none), clearing the queue.
std::string takeOpensslError();

}  // namespace garmcap::daemon
