#include "garmcap/daemon/http_server.h"

#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/ssl.hpp>

#include "garmcap/daemon/http_session.h"

namespace garmcap::daemon {

namespace asio = boost::asio;
namespace beast = boost::beast;
using tcp = asio::ip::tcp;

bool needsToken(std::string_view path) {
  return path.rfind("/api/", 0) == 0 || path == "/api" || path.rfind("/stream", 0) == 0;
}

bool authorized(const Request& request, const std::string& token, const LoginSessions* logins) {
  if (token.empty())
    return true;
  if (logins) {
    const auto cookie = request[http::field::cookie];
    if (auto id = cookieValue(std::string_view(cookie.data(), cookie.size()), kSessionCookie))
      if (logins->valid(*id))
        return true;
  }
  // Constant time in the token's length: no early exit on the first wrong byte.
  auto equal = [&](std::string_view given) { return constantTimeEqual(given, token); };
  // RFC 7235: the scheme is case-insensitive ("bearer", "BEARER"), one or more spaces follow.
  auto auth = request[http::field::authorization];
  std::string_view a(auth.data(), auth.size());
  if (a.size() > 7 && beast::iequals(beast::string_view(a.data(), 6), "Bearer") && a[6] == ' ') {
    a.remove_prefix(7);
    while (!a.empty() && a.front() == ' ')
      a.remove_prefix(1);
    if (equal(a))
      return true;
  }
  if (request.method() == http::verb::get) {
    const auto target = request.target();
    const std::string_view t(target.data(), target.size());
    const std::size_t q = t.find('?');
    if (q != std::string_view::npos) {
      std::string_view query = t.substr(q + 1);
      while (!query.empty()) {
        const std::size_t amp = query.find('&');
        const std::string_view pair = query.substr(0, amp);
        if (pair.rfind("token=", 0) == 0 && equal(pair.substr(6)))
          return true;
        if (amp == std::string_view::npos)
          break;
        query = query.substr(amp + 1);
      }
    }
  }
  return false;
}

namespace {

class Listener : public std::enable_shared_from_this<Listener> {
 public:
  Listener(asio::io_context& io, std::shared_ptr<ServerShared> shared)
      : io_(io), acceptor_(asio::make_strand(io)), shared_(std::move(shared)) {}

  void open(const tcp::endpoint& endpoint) {
    beast::error_code ec;
    acceptor_.open(endpoint.protocol(), ec);
    if (!ec)
      acceptor_.set_option(asio::socket_base::reuse_address(true), ec);
    if (!ec)
      acceptor_.bind(endpoint, ec);
    if (!ec)
      acceptor_.listen(asio::socket_base::max_listen_connections, ec);
    if (ec)
      throw std::runtime_error("http: cannot listen on " + endpoint.address().to_string() + ":" +
                               std::to_string(endpoint.port()) + ": " + ec.message());
  }
  void run() { doAccept(); }
  void stop() {
    asio::post(acceptor_.get_executor(), [self = shared_from_this()] {
      beast::error_code ec;
      self->acceptor_.close(ec);
    });
  }
  std::uint16_t port() const { return acceptor_.local_endpoint().port(); }

 private:
  void doAccept() {
    acceptor_.async_accept(asio::make_strand(io_),
                           beast::bind_front_handler(&Listener::onAccept, shared_from_this()));
  }
  void onAccept(beast::error_code ec, tcp::socket socket) {
    if (ec == asio::error::operation_aborted || !acceptor_.is_open())
      return;
    if (!ec)
      admit(std::move(socket));
    doAccept();
  }

  // A client over its own limit gives up the slot of its connection that has waited longest
  // for a request header, or is refused; then, with every slot of the server taken, the new
  // client takes the slot of whichever connection has waited longest; only when every slot is
  // busy serving is the answer 503.
  void admit(tcp::socket socket) {
    beast::error_code aec;
    const auto peer = socket.remote_endpoint(aec);
    if (aec)
      return;  // gone already
    const std::string address = peer.address().to_string();
    const int perClient = shared_->config.maxConnectionsPerClient;
    auto slot = shared_->clients.acquire(address, perClient);
    if (!slot && shared_->waiting.evictOldest(address))
      slot = shared_->clients.acquire(address, perClient, /*force=*/true);
    if (!slot) {
      refuse(socket, "too many connections from this client");
      return;
    }
    if (shared_->sessions.load() >= shared_->config.maxConnections &&
        !shared_->waiting.evictOldest()) {
      refuse(socket, "too many connections");
      return;
    }
    if (shared_->tls)
      serveConnection(beast::ssl_stream<beast::tcp_stream>(std::move(socket), *shared_->tls),
                      shared_, std::move(slot));
    else
      serveConnection(beast::tcp_stream(std::move(socket)), shared_, std::move(slot));
  }

  // A short answer instead of silently queueing the client.
  static void refuse(tcp::socket& socket, const std::string& why) {
    const std::string body = "{\"error\": \"" + why + "\"}";
    const std::string answer =
        "HTTP/1.1 503 Service Unavailable\r\nContent-Type: application/json\r\nRetry-After: "
        "1\r\nContent-Length: " +
        std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body;
    beast::error_code wec;
    asio::write(socket, asio::buffer(answer), wec);
    socket.close(wec);
  }

  asio::io_context& io_;
  tcp::acceptor acceptor_;
  std::shared_ptr<ServerShared> shared_;
};

}  // namespace

HttpServer::HttpServer(asio::io_context& io, const Config& config, const Router& router,
                       const StaticFiles& files, std::shared_ptr<boost::asio::ssl::context> tls)
    : io_(io), shared_(new ServerShared{config, router, files, std::move(tls)}) {}

HttpServer::~HttpServer() {
  stop();
}

void HttpServer::start() {
  beast::error_code ec;
  const auto address = asio::ip::make_address(shared_->config.listenAddress, ec);
  if (ec)
    throw std::runtime_error("http: bad listen address '" + shared_->config.listenAddress + "'");
  auto listener = std::make_shared<Listener>(io_, shared_);
  listener->open(tcp::endpoint(address, shared_->config.listenPort));
  listener->run();
  listener_ = listener;
}

void HttpServer::stop() {
  if (listener_)
    static_cast<Listener*>(listener_.get())->stop();
}

std::uint16_t HttpServer::port() const {
  return listener_ ? static_cast<Listener*>(listener_.get())->port() : 0;
}

}  // namespace garmcap::daemon
