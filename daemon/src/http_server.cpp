#include "garmcap/daemon/http_server.h"

#include <spdlog/spdlog.h>

#include <boost/asio/dispatch.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/core.hpp>
#include <deque>

namespace garmcap::daemon {

namespace asio = boost::asio;
namespace beast = boost::beast;
using tcp = asio::ip::tcp;

bool needsToken(std::string_view path) {
  return path.rfind("/api/", 0) == 0 || path == "/api" || path.rfind("/stream", 0) == 0;
}

bool authorized(const Request& request, const std::string& token) {
  if (token.empty())
    return true;
  auto equal = [&](std::string_view given) {
    // Constant time in the token's length: no early exit on the first wrong byte.
    unsigned diff = given.size() == token.size() ? 0u : 1u;
    for (std::size_t i = 0; i < token.size(); ++i)
      diff |= static_cast<unsigned>(token[i] ^ (i < given.size() ? given[i] : 0));
    return diff == 0;
  };
  auto auth = request[http::field::authorization];
  const std::string_view a(auth.data(), auth.size());
  if (a.rfind("Bearer ", 0) == 0 && equal(a.substr(7)))
    return true;
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

struct HttpServer::Shared {
  Config config;
  const Router& router;
  const StaticFiles& files;
  std::atomic<int> sessions{0};
  std::atomic<bool> stopped{false};
};

namespace {

class Session;

// Long-lived response over a session: raw header then raw chunks, bounded queue.
class SessionSink : public StreamSink, public std::enable_shared_from_this<SessionSink> {
 public:
  SessionSink(std::shared_ptr<Session> session, std::size_t maxQueued)
      : session_(session), maxQueued_(maxQueued) {}
  void writeHeader(Response header) override;
  void write(std::string chunk) override;
  bool open() const override { return open_; }
  void close() override;
  void markClosed() { open_ = false; }

 private:
  std::weak_ptr<Session> session_;
  std::size_t maxQueued_;
  std::atomic<bool> open_{true};
};

class Session : public std::enable_shared_from_this<Session> {
 public:
  Session(tcp::socket&& socket, std::shared_ptr<HttpServer::Shared> shared)
      : stream_(std::move(socket)), shared_(std::move(shared)) {
    ++shared_->sessions;
  }
  ~Session() { --shared_->sessions; }

  void run() {
    asio::dispatch(stream_.get_executor(),
                   beast::bind_front_handler(&Session::doRead, shared_from_this()));
  }

  // Stream mode ----------------------------------------------------------------------------
  void queueRaw(std::string data, std::size_t maxQueued) {
    asio::post(stream_.get_executor(),
               [self = shared_from_this(), data = std::move(data), maxQueued]() mutable {
                 if (self->streamClosed_)
                   return;
                 self->rawQueue_.push_back(std::move(data));
                 // Drop the oldest unsent chunk (never the one being written) when a client is
                 // slow: a preview or event stream must not back up into the station.
                 while (self->rawQueue_.size() > maxQueued + (self->rawWriting_ ? 1 : 0))
                   self->rawQueue_.erase(self->rawQueue_.begin() + (self->rawWriting_ ? 1 : 0));
                 if (!self->rawWriting_)
                   self->writeRaw();
               });
  }
  void closeStream() {
    asio::post(stream_.get_executor(), [self = shared_from_this()] {
      self->streamClosed_ = true;
      if (!self->rawWriting_)
        self->shutdown();
    });
  }
  std::shared_ptr<SessionSink> sink_;

 private:
  void doRead() {
    parser_.emplace();
    parser_->body_limit(shared_->config.bodyLimitBytes);
    parser_->header_limit(16 * 1024);
    stream_.expires_after(std::chrono::seconds(shared_->config.requestTimeoutS));
    http::async_read(stream_, buffer_, *parser_,
                     beast::bind_front_handler(&Session::onRead, shared_from_this()));
  }

  void onRead(beast::error_code ec, std::size_t) {
    if (ec == http::error::end_of_stream || ec == asio::error::eof)
      return shutdown();
    if (ec == beast::error::timeout)
      return;  // stream closed by the timeout
    if (ec == http::error::body_limit) {
      return sendError(
          http::status::payload_too_large,
          "request body larger than " + std::to_string(shared_->config.bodyLimitBytes) + " bytes",
          false);
    }
    if (ec == http::error::header_limit)
      return sendError(http::status::request_header_fields_too_large, "request header too large",
                       false);
    if (ec) {
      if (ec == asio::error::operation_aborted || ec == asio::error::connection_reset)
        return;
      return sendError(http::status::bad_request, "malformed request: " + ec.message(), false);
    }
    Request req = parser_->release();
    handle(std::move(req));
  }

  void handle(Request req) {
    const auto target = req.target();
    const std::string_view t(target.data(), target.size());
    const std::string_view path = t.substr(0, t.find('?'));
    const bool keepAlive = req.keep_alive();
    if (needsToken(path) && !authorized(req, shared_->config.token)) {
      Response res = jsonError(http::status::unauthorized, "missing or wrong bearer token");
      res.set(http::field::www_authenticate, "Bearer realm=\"garmcapd\"");
      return send(std::move(res), keepAlive);
    }
    if (needsToken(path)) {
      auto m = shared_->router.find(req.method(), t);
      if (m.stream) {
        // The session becomes a one-way stream until the client goes away.
        stream_.expires_never();
        sink_ = std::make_shared<SessionSink>(shared_from_this(), 16);
        try {
          (*m.stream)(req, m.match, sink_);
        } catch (const std::exception& e) {
          spdlog::error("http: stream handler failed: {}", e.what());
          sink_->close();
        }
        watchPeer();
        return;
      }
      auto self = shared_from_this();
      const unsigned version = req.version();
      shared_->router.dispatch(req, [self, keepAlive, version](Response res) {
        res.version(version);
        asio::post(self->stream_.get_executor(), [self, res = std::move(res), keepAlive]() mutable {
          self->send(std::move(res), keepAlive);
        });
      });
      return;
    }
    if (req.method() != http::verb::get && req.method() != http::verb::head)
      return sendError(http::status::method_not_allowed, "only GET is allowed here", keepAlive);
    if (auto res = shared_->files.serve(path, req.version(), keepAlive)) {
      if (req.method() == http::verb::head) {
        const auto n = res->body().size();
        res->body().clear();
        res->content_length(n);
      }
      return send(std::move(*res), keepAlive);
    }
    sendError(http::status::not_found, "no such resource", keepAlive);
  }

  void sendError(http::status status, const std::string& message, bool keepAlive) {
    send(jsonError(status, message), keepAlive);
  }

  void send(Response res, bool keepAlive) {
    res.keep_alive(keepAlive);
    res.set(http::field::server, "garmcapd");
    res.set("X-Content-Type-Options", "nosniff");
    if (!res.has_content_length())
      res.prepare_payload();
    auto sp = std::make_shared<Response>(std::move(res));
    stream_.expires_after(std::chrono::seconds(shared_->config.requestTimeoutS));
    http::async_write(stream_, *sp,
                      [self = shared_from_this(), sp](beast::error_code ec, std::size_t) {
                        if (ec)
                          return;
                        if (sp->need_eof())
                          return self->shutdown();
                        self->doRead();
                      });
  }

  void writeRaw() {
    if (rawQueue_.empty()) {
      if (streamClosed_)
        shutdown();
      return;
    }
    rawWriting_ = true;
    asio::async_write(stream_.socket(), asio::buffer(rawQueue_.front()),
                      [self = shared_from_this()](beast::error_code ec, std::size_t) {
                        self->rawWriting_ = false;
                        self->rawQueue_.pop_front();
                        if (ec) {
                          self->streamClosed_ = true;
                          if (self->sink_)
                            self->sink_->markClosed();
                          self->rawQueue_.clear();
                          return;
                        }
                        self->writeRaw();
                      });
  }

  // A streaming client sends nothing more; a read completing (EOF or error) means it left.
  void watchPeer() {
    auto buf = std::make_shared<std::array<char, 256>>();
    stream_.socket().async_read_some(
        asio::buffer(*buf), [self = shared_from_this(), buf](beast::error_code ec, std::size_t) {
          if (!ec)
            return self->watchPeer();
          self->streamClosed_ = true;
          if (self->sink_)
            self->sink_->markClosed();
        });
  }

  void shutdown() {
    beast::error_code ec;
    stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
  }

  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  std::shared_ptr<HttpServer::Shared> shared_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::deque<std::string> rawQueue_;
  bool rawWriting_ = false;
  bool streamClosed_ = false;
};

void SessionSink::writeHeader(Response header) {
  auto s = session_.lock();
  if (!s || !open_)
    return;
  std::string head = "HTTP/1.1 " + std::to_string(header.result_int()) + " " +
                     std::string(header.reason().data(), header.reason().size()) + "\r\n";
  for (const auto& f : header)
    head += std::string(f.name_string().data(), f.name_string().size()) + ": " +
            std::string(f.value().data(), f.value().size()) + "\r\n";
  head += "Connection: close\r\nX-Content-Type-Options: nosniff\r\n\r\n";
  s->queueRaw(std::move(head), maxQueued_);
}

void SessionSink::write(std::string chunk) {
  auto s = session_.lock();
  if (!s || !open_)
    return;
  s->queueRaw(std::move(chunk), maxQueued_);
}

void SessionSink::close() {
  open_ = false;
  if (auto s = session_.lock())
    s->closeStream();
}

class Listener : public std::enable_shared_from_this<Listener> {
 public:
  Listener(asio::io_context& io, std::shared_ptr<HttpServer::Shared> shared)
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
    if (!ec) {
      if (shared_->sessions.load() >= shared_->config.maxConnections) {
        // Over the limit: a short answer instead of silently queueing the client.
        static const char kBusy[] =
            "HTTP/1.1 503 Service Unavailable\r\nContent-Type: application/json\r\n"
            "Content-Length: 33\r\nConnection: close\r\n\r\n{\"error\": \"too many connections\"}";
        beast::error_code wec;
        asio::write(socket, asio::buffer(kBusy, sizeof(kBusy) - 1), wec);
        socket.close(wec);
      } else {
        std::make_shared<Session>(std::move(socket), shared_)->run();
      }
    }
    doAccept();
  }

  asio::io_context& io_;
  tcp::acceptor acceptor_;
  std::shared_ptr<HttpServer::Shared> shared_;
};

}  // namespace

HttpServer::HttpServer(asio::io_context& io, const Config& config, const Router& router,
                       const StaticFiles& files)
    : io_(io), shared_(new Shared{config, router, files}) {}

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
