#pragma once
// The HTTP server (Boost.Beast 1.74, after example/advanced/server): a listener, one session per
// connection with its own strand, plain or TLS, a request body limit, a read timeout, a connection
// limit, the bearer-token check, and the split between API routes (Router), streams (StreamSink)
// and static files (StaticFiles). Handlers never see the socket.

#include <atomic>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl/context.hpp>
#include <cstdint>
#include <memory>
#include <string>

#include "garmcap/daemon/config.h"
#include "garmcap/daemon/http_router.h"

namespace garmcap::daemon {

struct ServerShared;  // http_session.h
class LoginSessions;  // login_sessions.h

/// True when the request carries the token ("Authorization: Bearer <token>", or `?token=` on a
/// GET, for EventSource and <img> which cannot set headers). Constant-time compare. An empty
/// token means "no token configured": every request is allowed (loopback binding only).
/// With `logins`, a live session cookie (POST /api/session, login_sessions.h) counts too.
bool authorized(const Request& request, const std::string& token,
                const LoginSessions* logins = nullptr);

/// Paths that need the token when one is configured: the API and the preview stream. Static UI
/// files do not (they hold no data).
bool needsToken(std::string_view path);

class HttpServer {
 public:
  /// With `tls` (tls_context.h), every connection is HTTPS; without, plain HTTP.
  HttpServer(boost::asio::io_context& io, const Config& config, const Router& router,
             const StaticFiles& files, std::shared_ptr<boost::asio::ssl::context> tls = nullptr);
  ~HttpServer();
  /// Binds and starts accepting. Throws std::runtime_error naming the address on failure.
  void start();
  /// Stops accepting and closes idle sessions.
  void stop();
  /// The bound port (useful with port 0).
  std::uint16_t port() const;

 private:
  boost::asio::io_context& io_;
  std::shared_ptr<ServerShared> shared_;
  std::shared_ptr<void> listener_;
};

}  // namespace garmcap::daemon
