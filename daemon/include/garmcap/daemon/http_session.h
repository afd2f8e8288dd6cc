#pragma once
// Internal to the HTTP server: one connection (Beast 1.74 advanced-server session), a template
// over the stream type so that unit tests drive the very same code over beast::test::stream, with
// no socket (tests/daemon/http_session_test.cpp). The server instantiates it for beast::tcp_stream
// and, with a TLS context (the hub), for beast::ssl_stream<beast::tcp_stream>: the TLS session
// first does the server handshake within header_timeout_s, counted as waiting for a header (a
// client that never finishes it holds no thread and can be evicted), and ends with close_notify.
// Nothing but http_server.cpp and its tests should include this header.
//
// Per request: body limit and header limit (413/431 JSON), read timeout (tcp only), the bearer
// token for API and stream paths, then the router (JSON API), a stream handler (SSE, MJPEG: the
// session turns into a one-way byte stream) or the static-file whitelist.

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <boost/asio/dispatch.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/socket_base.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/core/detect_ssl.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl/ssl_stream.hpp>
#include <chrono>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "garmcap/daemon/client_connections.h"
#include "garmcap/daemon/config.h"
#include "garmcap/daemon/download_sink.h"
#include "garmcap/daemon/http_guard.h"
#include "garmcap/daemon/http_router.h"
#include "garmcap/daemon/http_server.h"
#include "garmcap/daemon/login_sessions.h"

namespace garmcap::daemon {

/// A session that can be told to go away (the listener makes room for a new client).
class Evictable {
 public:
  virtual ~Evictable() = default;
  virtual void evict() = 0;
};

/// The sessions waiting for a request's header, oldest first. When every connection slot is
/// taken, a new client takes the slot of the one that has waited longest: clients that connect
/// and then send nothing (or a byte a second) cannot lock out one that sends its request at once.
class WaitingSessions {
 public:
  using Handle = std::uint64_t;  // removing a handle twice, or after an eviction, is harmless
  Handle add(std::weak_ptr<Evictable> s, std::string client = {}) {
    std::lock_guard lock(mutex_);
    const Handle h = next_++;
    waiting_.emplace(h, Entry{std::move(s), std::move(client)});
    return h;
  }
  void remove(Handle h) {
    std::lock_guard lock(mutex_);
    waiting_.erase(h);
  }
  /// Evicts the oldest waiting session still alive (of `client` only, when given); false when
  /// none waits.
  bool evictOldest(const std::optional<std::string>& client = std::nullopt) {
    std::shared_ptr<Evictable> victim;
    {
      std::lock_guard lock(mutex_);
      for (auto it = waiting_.begin(); it != waiting_.end() && !victim;) {
        if (client && it->second.client != *client) {
          ++it;
          continue;
        }
        victim = it->second.session.lock();
        it = waiting_.erase(it);
      }
    }
    if (!victim)
      return false;
    victim->evict();
    return true;
  }

 private:
  std::mutex mutex_;
  Handle next_ = 0;
  struct Entry {
    std::weak_ptr<Evictable> session;
    std::string client;  // the peer's address ("" where there is none: test streams)
  };
  std::map<Handle, Entry> waiting_;  // oldest first
};

/// What every session of one server shares. The router and files outlive the server.
struct ServerShared {
  Config config;
  const Router& router;
  const StaticFiles& files;
  // Set: every connection is TLS (beast::ssl_stream); the listener makes each stream from it.
  std::shared_ptr<boost::asio::ssl::context> tls{};
  std::atomic<int> sessions{0};
  WaitingSessions waiting{};
  ClientConnections clients{};
  LoginSessions logins{};
};

/// The longest a response, or a download's piece, of `bytes` may take to write: the request
/// timeout plus the time at `minSendRate` ([http] min_send_rate, Config::minSendRate), so a
/// large download to a slow (not stalled) client is not cut, and a stalled one is.
inline std::chrono::seconds writeDeadline(std::size_t bytes, int requestTimeoutS,
                                          std::size_t minSendRate) {
  return std::chrono::seconds(requestTimeoutS +
                              static_cast<long>(bytes / std::max<std::size_t>(minSendRate, 1)));
}

namespace detail {

namespace asio = boost::asio;
namespace beast = boost::beast;

// A long-lived response over a session: raw header, then raw chunks, through a bounded queue.
class SessionSinkBase : public StreamSink {
 public:
  bool open() const override { return open_; }
  void markClosed() { open_ = false; }

 protected:
  std::atomic<bool> open_{true};
};

template <class Stream>
class Session : public Evictable, public std::enable_shared_from_this<Session<Stream>> {
 public:
  Session(Stream&& stream, std::shared_ptr<ServerShared> shared,
          std::optional<ClientConnections::Slot> client = std::nullopt)
      : stream_(std::move(stream)), shared_(std::move(shared)), client_(std::move(client)) {
    ++shared_->sessions;
  }
  ~Session() override {
    stopWaiting();
    --shared_->sessions;
  }

  void evict() override {
    asio::post(stream_.get_executor(), [self = this->shared_from_this()] { self->closeNow(); });
  }

  void run() {
    if constexpr (kTls)
      asio::dispatch(stream_.get_executor(),
                     beast::bind_front_handler(&Session::doHandshake, this->shared_from_this()));
    else
      asio::dispatch(stream_.get_executor(),
                     beast::bind_front_handler(&Session::doRead, this->shared_from_this()));
  }

  // Stream mode ----------------------------------------------------------------------------
  // `drained` set: a download's piece (DownloadSink), never dropped; called once written, or
  // at once when the peer is gone.
  void queueRaw(std::string data, std::size_t maxQueued, std::function<void()> drained = {}) {
    asio::post(stream_.get_executor(), [self = this->shared_from_this(), data = std::move(data),
                                        maxQueued, drained = std::move(drained)]() mutable {
      if (self->streamClosed_) {
        if (drained)
          drained();
        return;
      }
      self->rawQueue_.push_back({std::move(data), std::move(drained)});
      // Drop the oldest unsent chunk (never the one being written, nor a download's piece) when
      // a client is slow: a preview or event stream must not back up into the station.
      while (self->rawQueue_.size() > maxQueued + (self->rawWriting_ ? 1 : 0)) {
        auto droppable =
            std::find_if(self->rawQueue_.begin() + (self->rawWriting_ ? 1 : 0),
                         self->rawQueue_.end(), [](const RawPiece& p) { return !p.drained; });
        if (droppable == self->rawQueue_.end())
          break;
        self->rawQueue_.erase(droppable);
      }
      if (!self->rawWriting_)
        self->writeRaw();
    });
  }
  void closeStream() {
    asio::post(stream_.get_executor(), [self = this->shared_from_this()] {
      self->streamClosed_ = true;
      if (!self->rawWriting_)
        self->shutdown();
    });
  }

 private:
  class Sink : public SessionSinkBase, public DownloadSink {
   public:
    Sink(std::shared_ptr<Session> session, std::size_t maxQueued)
        : session_(session), maxQueued_(maxQueued) {}
    void writeHeader(Response header) override {
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
    void write(std::string chunk) override {
      auto s = session_.lock();
      if (!s || !open_)
        return;
      s->queueRaw(std::move(chunk), maxQueued_);
    }
    void writeThen(std::string piece, std::function<void()> drained) override {
      auto s = session_.lock();
      if (!s || !open_)
        return drained();
      s->queueRaw(std::move(piece), maxQueued_, std::move(drained));
    }
    void close() override {
      open_ = false;
      if (auto s = session_.lock())
        s->closeStream();
    }

   private:
    std::weak_ptr<Session> session_;
    std::size_t maxQueued_;
  };

  static constexpr bool kTls = requires(Stream & st) {
    st.async_handshake(asio::ssl::stream_base::server, [](auto) {});
  };
  // The TCP stream, under TLS or not, has timeouts; the test stream has none (and needs none).
  auto& lowest() { return beast::get_lowest_layer(stream_); }
  static constexpr bool kTimed = requires(Stream & st) {
    beast::get_lowest_layer(st).expires_after(std::chrono::seconds(1));
  };
  void expiresAfter(std::chrono::seconds s) {
    if constexpr (kTimed)
      lowest().expires_after(s);
  }
  void expiresNever() {
    if constexpr (kTimed)
      lowest().expires_never();
  }

  // A client that connects and never completes the handshake (a plain-HTTP request, a port
  // scan, a slow client) is dropped after header_timeout_s, or sooner when its slot is needed.
  // The first bytes are looked at before the handshake (as nginx does for its 497): a TLS client
  // opens with a handshake record, and anything else, such as a plain-HTTP request typed as
  // http://, is told in plain text that the port speaks HTTPS instead of a silent close.
  void doHandshake() {
    expiresAfter(std::chrono::seconds(shared_->config.headerTimeoutS));
    waitingHandle_ =
        shared_->waiting.add(this->weak_from_this(), client_ ? client_->address() : std::string());
    beast::async_detect_ssl(
        lowest(), buffer_, beast::bind_front_handler(&Session::onDetect, this->shared_from_this()));
  }
  void onDetect(beast::error_code ec, bool tls) {
    if (ec) {
      spdlog::debug("http: {} left before its TLS handshake: {}",
                    client_ ? client_->address() : std::string("a client"), ec.message());
      return;
    }
    if (!tls)
      return refusePlainHttp();
    // The bytes read to decide are the start of the ClientHello: the handshake takes them.
    stream_.async_handshake(
        asio::ssl::stream_base::server, buffer_.data(),
        beast::bind_front_handler(&Session::onHandshake, this->shared_from_this()));
  }
  void onHandshake(beast::error_code ec, std::size_t used) {
    if (ec) {
      // Not an error of the server: a client that trusts another CA, offers only old TLS, or left.
      spdlog::debug("http: TLS handshake with {} failed: {}",
                    client_ ? client_->address() : std::string("a client"), ec.message());
      return;  // the stream closes with the session
    }
    buffer_.consume(used);
    doRead();
  }
  // A 400 in plain text on the bare TCP stream, then the sending side is shut and what the
  // client still sends is read and dropped for a moment (a close with unread bytes would reset
  // the connection, and the client could lose the answer), then the socket closes.
  void refusePlainHttp() {
    stopWaiting();
    spdlog::debug("http: {} spoke plain HTTP to the TLS port; answered 400",
                  client_ ? client_->address() : std::string("a client"));
    static const std::string kBody =
        "400 Bad Request: this port speaks HTTPS only. Use an https:// URL.\n";
    auto answer = std::make_shared<std::string>(
        "HTTP/1.1 400 Bad Request\r\nContent-Type: text/plain; charset=utf-8\r\n"
        "Content-Length: " +
        std::to_string(kBody.size()) + "\r\nConnection: close\r\n\r\n" + kBody);
    expiresAfter(std::chrono::seconds(2));
    asio::async_write(lowest(), asio::buffer(*answer),
                      [self = this->shared_from_this(), answer](beast::error_code ec, std::size_t) {
                        if (ec)
                          return;
                        beast::error_code ignored;
                        self->lowest().socket().shutdown(asio::socket_base::shutdown_send, ignored);
                        self->drainThenClose();
                      });
  }
  void drainThenClose() {
    auto buf = std::make_shared<std::array<char, 1024>>();
    lowest().async_read_some(asio::buffer(*buf), [self = this->shared_from_this(), buf](
                                                     beast::error_code ec, std::size_t) {
      if (!ec)
        return self->drainThenClose();
      beast::error_code ignored;
      self->lowest().socket().close(ignored);
    });
  }

  // A request is read in two steps: the header within header_timeout_s of the connection (or of
  // the previous answer: the keep-alive idle time), then the body within request_timeout_s.
  void doRead() {
    parser_.emplace();
    parser_->body_limit(shared_->config.bodyLimitBytes);
    parser_->header_limit(16 * 1024);
    expiresAfter(std::chrono::seconds(shared_->config.headerTimeoutS));
    if (!waitingHandle_)
      waitingHandle_ = shared_->waiting.add(this->weak_from_this(),
                                            client_ ? client_->address() : std::string());
    http::async_read_header(
        stream_, buffer_, *parser_,
        beast::bind_front_handler(&Session::onHeader, this->shared_from_this()));
  }

  void onHeader(beast::error_code ec, std::size_t n) {
    stopWaiting();
    if (ec || parser_->is_done())
      return onRead(ec, n);
    expiresAfter(std::chrono::seconds(shared_->config.requestTimeoutS));
    http::async_read(stream_, buffer_, *parser_,
                     beast::bind_front_handler(&Session::onRead, this->shared_from_this()));
  }

  void stopWaiting() {
    if (waitingHandle_) {
      shared_->waiting.remove(*waitingHandle_);
      waitingHandle_.reset();
    }
  }

  void closeNow() {
    if constexpr (requires(Stream & st) { beast::get_lowest_layer(st).socket(); }) {
      beast::error_code ec;
      lowest().socket().close(ec);
    } else {
      stream_.close();
    }
  }

  void onRead(beast::error_code ec, std::size_t) {
    if (ec == http::error::end_of_stream || ec == asio::error::eof)
      return shutdown();
    // A TLS client that closed its socket without close_notify, between requests.
    if constexpr (kTls)
      if (ec == asio::ssl::error::stream_truncated)
        return;
    if (ec == beast::error::timeout)
      return;  // stream closed by the timeout
    // After a framing error the rest of the connection cannot be trusted: answer and close.
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

  // No exception may leave a completion handler: it would escape io.run() and stop the daemon.
  void handle(Request req) {
    try {
      route(std::move(req));
    } catch (const std::exception& e) {
      spdlog::error("http: request failed before an answer: {}", e.what());
      sendError(http::status::internal_server_error,
                "internal error; the station's log has the details", false);
    } catch (...) {
      spdlog::error("http: request failed before an answer (non-standard exception)");
      sendError(http::status::internal_server_error,
                "internal error; the station's log has the details", false);
    }
  }

  void route(Request req) {
    if (auto refusal = refuseRequest(req, shared_->config.serverNames))
      return sendError(refusal->status, refusal->message, false);
    const auto target = req.target();
    const std::string_view t(target.data(), target.size());
    const std::string_view path = t.substr(0, t.find('?'));
    const bool keepAlive = req.keep_alive();
    // The station's log-in, unless the router has a /api/session of its own (the hub's, whose
    // callers are station and admin tokens, not this log-in).
    if (path == "/api/session" && !shared_->router.find(req.method(), t).pathMatched)
      return send(login(req), keepAlive);
    if (needsToken(path) && !authorized(req, shared_->config.token, &shared_->logins)) {
      Response res = jsonError(http::status::unauthorized, "missing or wrong bearer token");
      res.set(http::field::www_authenticate, "Bearer realm=\"garmcapd\"");
      return send(std::move(res), keepAlive);
    }
    if (needsToken(path)) {
      auto m = shared_->router.find(req.method(), t);
      if (m.stream) {
        // The session becomes a one-way stream until the client goes away.
        expiresNever();
        sink_ = std::make_shared<Sink>(this->shared_from_this(), 16);
        try {
          (*m.stream)(req, m.match, sink_);
        } catch (const std::exception& e) {
          spdlog::error("http: stream handler failed: {}", e.what());
          sink_->close();
        }
        watchPeer();
        return;
      }
      auto self = this->shared_from_this();
      const unsigned version = req.version();
      const bool head = req.method() == http::verb::head;
      // A handler answers once; a second answer (a handler that replied, then threw) would be a
      // second write racing the first on this stream, so it is dropped and logged.
      auto answered = std::make_shared<std::atomic<bool>>(false);
      shared_->router.dispatch(req, [self, keepAlive, version, head, answered](Response res) {
        if (answered->exchange(true)) {
          spdlog::error("http: a handler answered twice; the second answer ({}) is dropped",
                        res.result_int());
          return;
        }
        res.version(version);
        if (head) {
          const auto n = res.body().size();
          res.body().clear();
          res.content_length(n);
        }
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

  // POST {"token": ...}: the token for a session cookie; DELETE: log out; GET: whether this
  // browser is logged in. Without a configured token everyone is, and no cookie is made.
  Response login(const Request& req) {
    const std::string& token = shared_->config.token;
    const auto cookieField = req[http::field::cookie];
    const auto cookie =
        cookieValue(std::string_view(cookieField.data(), cookieField.size()), kSessionCookie);
    auto answer = [&](http::status st, bool in) {
      Response res = jsonResponse(st, {{"authenticated", in}, {"token_required", !token.empty()}});
      return res;
    };
    auto setCookie = [&](Response& res, const std::string& value, long maxAge) {
      res.set(http::field::set_cookie,
              std::string(kSessionCookie) + "=" + value +
                  "; Path=/; HttpOnly; SameSite=Strict; Max-Age=" + std::to_string(maxAge));
    };
    if (req.method() == http::verb::get)
      return answer(http::status::ok, authorized(req, token, &shared_->logins));
    if (req.method() == http::verb::delete_) {
      if (cookie)
        shared_->logins.revoke(*cookie);
      Response res = answer(http::status::ok, token.empty());
      setCookie(res, "", 0);
      return res;
    }
    if (req.method() != http::verb::post)
      return jsonError(http::status::method_not_allowed, "use GET, POST or DELETE here");
    nlohmann::json body;
    try {
      body = parseJsonBody(req);
    } catch (const BadRequest& e) {
      return jsonError(http::status::bad_request, e.what());
    }
    if (!body.is_object() || !body.contains("token") || !body["token"].is_string() ||
        body.size() != 1)
      return jsonError(http::status::bad_request, R"(body must be {"token": "..."})");
    if (token.empty())
      return answer(http::status::ok, true);
    if (!constantTimeEqual(body["token"].get<std::string>(), token)) {
      spdlog::warn("http: a log-in with a wrong token");
      return jsonError(http::status::unauthorized, "wrong token");
    }
    Response res = answer(http::status::ok, true);
    setCookie(res, shared_->logins.create(), shared_->logins.lifetime().count());
    return res;
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
    expiresAfter(writeDeadline(sp->body().size(), shared_->config.requestTimeoutS,
                               shared_->config.minSendRate));
    http::async_write(stream_, *sp,
                      [self = this->shared_from_this(), sp](beast::error_code ec, std::size_t) {
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
    // A download's piece (DownloadSink) must be written within the deadline its size gives, as
    // a whole response is: a client that stops reading is cut, its connection closed, and the
    // writer told (drained, with the sink closed), which frees its export slot. A preview or
    // event stream's chunks have none: their slow clients lose chunks instead.
    if (rawQueue_.front().drained)
      expiresAfter(writeDeadline(rawQueue_.front().data.size(), shared_->config.requestTimeoutS,
                                 shared_->config.minSendRate));
    else
      expiresNever();
    asio::async_write(stream_, asio::buffer(rawQueue_.front().data),
                      [self = this->shared_from_this()](beast::error_code ec, std::size_t) {
                        self->rawWriting_ = false;
                        auto drained = std::move(self->rawQueue_.front().drained);
                        self->rawQueue_.pop_front();
                        if (ec) {
                          self->streamClosed_ = true;
                          if (self->sink_)
                            self->sink_->markClosed();
                          std::vector<std::function<void()>> waiting;
                          for (auto& p : self->rawQueue_)
                            if (p.drained)
                              waiting.push_back(std::move(p.drained));
                          self->rawQueue_.clear();
                          if (drained)
                            drained();
                          for (auto& w : waiting)
                            w();
                          return;
                        }
                        if (drained)
                          drained();
                        self->writeRaw();
                      });
  }

  // A streaming client sends nothing more; a read completing (EOF or error) means it left.
  void watchPeer() {
    auto buf = std::make_shared<std::array<char, 256>>();
    stream_.async_read_some(asio::buffer(*buf), [self = this->shared_from_this(), buf](
                                                    beast::error_code ec, std::size_t) {
      if (!ec)
        return self->watchPeer();
      self->streamClosed_ = true;
      if (self->sink_)
        self->sink_->markClosed();
    });
  }

  void shutdown() {
    if constexpr (kTls) {
      // close_notify, then the socket is closed; a peer that does not send its own
      // close_notify back is waited for one second.
      expiresAfter(std::chrono::seconds(1));
      stream_.async_shutdown([self = this->shared_from_this()](beast::error_code) {
        beast::error_code ec;
        self->lowest().socket().close(ec);
      });
    } else if constexpr (requires(Stream & st) { st.socket(); }) {
      beast::error_code ec;
      stream_.socket().shutdown(asio::socket_base::shutdown_send, ec);
    } else {
      stream_.close();
    }
  }

  Stream stream_;
  beast::flat_buffer buffer_;
  std::shared_ptr<ServerShared> shared_;
  std::optional<http::request_parser<http::string_body>> parser_;
  struct RawPiece {
    std::string data;
    std::function<void()> drained;  // set for a download's piece
  };
  std::deque<RawPiece> rawQueue_;
  bool rawWriting_ = false;
  bool streamClosed_ = false;
  std::shared_ptr<Sink> sink_;
  std::optional<WaitingSessions::Handle> waitingHandle_;
  std::optional<ClientConnections::Slot> client_;  // counts this connection against its peer
};

}  // namespace detail

/// Serves one connection on `stream` until the peer leaves. The session keeps itself alive
/// through its pending operations; `shared` counts it.
template <class Stream>
void serveConnection(Stream stream, std::shared_ptr<ServerShared> shared,
                     std::optional<ClientConnections::Slot> client = std::nullopt) {
  std::make_shared<detail::Session<Stream>>(std::move(stream), std::move(shared), std::move(client))
      ->run();
}

}  // namespace garmcap::daemon
