#include "garmcap/daemon/hub_pusher.h"

#include <spdlog/spdlog.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <future>
#include <stdexcept>

#include "garmcap/daemon/catalog.h"
#include "garmcap/daemon/content_store.h"
#include "garmcap/daemon/tls_context.h"

namespace garmcap::daemon {

namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace ssl = boost::asio::ssl;

constexpr auto kHttpTimeout = std::chrono::seconds(5);
constexpr int kBatch = 20;

// A failed exchange with the hub: retried after the backoff.
class HubUnreachable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The hub refused this station's token (401/403): nothing is parked, the pusher waits at its
// longest backoff and reports it until the token is right.
class HubTokenRefused : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The hub's certificate was not accepted, or the TLS handshake failed: retried with the
// backoff, reported in status() until a handshake succeeds.
class HubTlsFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct HubReply {
  int status = 0;
  std::string body;
};

// Runs one asynchronous operation on `io` to completion: the tcp_stream's timer (expires_after)
// bounds only asynchronous operations, so every step of a call goes through here.
template <typename Start>
beast::error_code runOne(asio::io_context& io, Start&& start) {
  beast::error_code result = asio::error::operation_aborted;
  start([&result](beast::error_code ec, auto&&...) { result = ec; });
  io.restart();
  io.run();
  return result;
}

bool isIpAddress(const std::string& host) {
  beast::error_code ec;
  asio::ip::make_address(host, ec);
  return !ec;
}

// The TLS handshake as a client of `hub`: SNI with its name (not for an IP literal, RFC 6066),
// the chain verified against the context's CA, and the name or IP checked against the
// certificate. A failure says why: the certificate error OpenSSL found, or the name mismatch.
void handshake(asio::io_context& io, beast::ssl_stream<beast::tcp_stream>& stream,
               const HubAddress& hub) {
  if (!isIpAddress(hub.host) && !SSL_set_tlsext_host_name(stream.native_handle(), hub.host.c_str()))
    throw HubTlsFailed("cannot set the TLS server name " + hub.host + ": " + takeOpensslError());
  auto why = std::make_shared<std::string>();
  stream.set_verify_callback([why, check = ssl::host_name_verification(hub.host), host = hub.host](
                                 bool preverified, ssl::verify_context& ctx) mutable {
    X509_STORE_CTX* store = ctx.native_handle();
    if (!preverified) {
      if (why->empty()) {
        char subject[256] = "";
        if (X509* cert = X509_STORE_CTX_get_current_cert(store))
          X509_NAME_oneline(X509_get_subject_name(cert), subject, sizeof subject);
        *why = std::string(X509_verify_cert_error_string(X509_STORE_CTX_get_error(store))) +
               " (certificate " + subject +
               "; is [hub] ca_file, or the system's store, the CA that signed it?)";
      }
      return false;
    }
    const bool ok = check(preverified, ctx);
    if (!ok && why->empty())
      *why = "the hub's certificate is not for " + host;
    return ok;
  });
  const auto ec = runOne(io, [&](auto&& done) {
    stream.async_handshake(ssl::stream_base::client, std::forward<decltype(done)>(done));
  });
  if (ec) {
    const std::string what = why->empty() ? ec.message() : *why;
    throw HubTlsFailed("TLS with " + hub.url() + " failed: " + what);
  }
}

// One request on a fresh connection (the hub may restart between any two); each step within
// kHttpTimeout.
HubReply call(const HubAddress& hub, ssl::context* tls, const std::string& token, http::verb verb,
              const std::string& target, std::string body = {},
              const std::string& contentType = {}) {
  asio::io_context io;
  asio::ip::tcp::resolver resolver(io);
  beast::error_code ec;
  const auto endpoints = resolver.resolve(hub.host, std::to_string(hub.port), ec);
  if (ec)
    throw HubUnreachable("cannot resolve " + hub.host + ": " + ec.message());
  beast::tcp_stream tcp(io);
  tcp.expires_after(kHttpTimeout);
  ec = runOne(io, [&](auto&& done) {
    tcp.async_connect(endpoints, [done](beast::error_code e, const auto&) mutable { done(e); });
  });
  if (ec)
    throw HubUnreachable("cannot connect to " + hub.host + ":" + std::to_string(hub.port) + ": " +
                         ec.message());
  http::request<http::string_body> req{verb, target, 11};
  req.set(http::field::host, hub.host + ":" + std::to_string(hub.port));
  req.set(http::field::authorization, "Bearer " + token);
  if (!contentType.empty())
    req.set(http::field::content_type, contentType);
  req.body() = std::move(body);
  req.prepare_payload();
  http::response_parser<http::string_body> parser;
  parser.body_limit(16u << 20);
  if (verb == http::verb::head)
    parser.skip(true);

  auto exchange = [&](auto& stream) {
    beast::get_lowest_layer(stream).expires_after(kHttpTimeout);
    auto e = runOne(io, [&](auto&& done) {
      http::async_write(stream, req, std::forward<decltype(done)>(done));
    });
    if (e)
      throw HubUnreachable(target + ": " + e.message());
    beast::flat_buffer buffer;
    beast::get_lowest_layer(stream).expires_after(kHttpTimeout);
    e = runOne(io, [&](auto&& done) {
      http::async_read(stream, buffer, parser, std::forward<decltype(done)>(done));
    });
    if (e)
      throw HubUnreachable(target + ": " + e.message());
  };
  if (tls) {
    beast::ssl_stream<beast::tcp_stream> stream(std::move(tcp), *tls);
    beast::get_lowest_layer(stream).expires_after(kHttpTimeout);
    handshake(io, stream, hub);
    exchange(stream);
    // close_notify; the answer is complete already, so a hub that does not reply costs 1 s.
    beast::get_lowest_layer(stream).expires_after(std::chrono::seconds(1));
    runOne(io, [&](auto&& done) { stream.async_shutdown(std::forward<decltype(done)>(done)); });
  } else {
    exchange(tcp);
    tcp.socket().shutdown(asio::ip::tcp::socket::shutdown_both, ec);
  }
  return {static_cast<int>(parser.get().result_int()), parser.get().body()};
}

bool ok(const HubReply& r) {
  return r.status >= 200 && r.status < 300;
}

// The hub's answer, shortened for the log, the status and the refused row.
std::string describe(const std::string& what, const HubReply& r) {
  return what + ": " + std::to_string(r.status) + " " + r.body.substr(0, 200);
}

}  // namespace

bool hubRefusesForGood(int status) {
  return status == 400 || status == 404 || status == 409 || status == 413 || status == 422;
}

bool hubRefusesToken(int status) {
  return status == 401 || status == 403;
}

namespace {

// For a failed reply: the refusal to park the row with, or an exception (a wrong token; or
// something a retry may change: 5xx, 408, 429, anything else).
std::pair<int, std::string> checkRefusal(const std::string& what, const HubReply& reply) {
  if (hubRefusesToken(reply.status))
    throw HubTokenRefused(describe(what, reply));
  if (!hubRefusesForGood(reply.status))
    throw HubUnreachable(describe(what, reply));
  return {reply.status, describe(what, reply)};
}

}  // namespace

std::chrono::milliseconds hubBackoff(int failures) {
  if (failures <= 0)
    return std::chrono::milliseconds(0);
  std::int64_t ms = 500;
  for (int i = 1; i < failures && ms < 30000; ++i)
    ms *= 2;
  return std::chrono::milliseconds(std::min<std::int64_t>(ms, 30000));
}

HubPusher::HubPusher(RouteContext& station, const Config& config)
    : station_(station), token_(config.hubToken), poll_(config.hubPollMs) {
  auto hub = parseHubUrl(config.hubUrl);
  if (!hub)
    throw ConfigError("[hub] url: not https://HOST:PORT or http://HOST:PORT: '" + config.hubUrl +
                      "'");
  hub_ = *hub;
  if (hub_.tls)
    tls_ = makeClientTlsContext(config.hubCaFile);
}

HubPusher::~HubPusher() {
  stop();
}

void HubPusher::start() {
  thread_ = std::thread([this] { run(); });
}

void HubPusher::stop() {
  stopping_ = true;
  wake_.notify_all();
  if (thread_.joinable())
    thread_.join();
}

namespace {

// Runs `fn` on the catalog's strand and waits for it (bounded by `stopping`).
template <typename T>
T onCatalog(RouteContext& station, const std::atomic<bool>& stopping,
            std::function<T(Catalog&)> fn) {
  auto promise = std::make_shared<std::promise<T>>();
  auto future = promise->get_future();
  station.withCatalog(
      [promise, fn](Catalog& c) {
        try {
          if constexpr (std::is_void_v<T>) {
            fn(c);
            promise->set_value();
          } else {
            promise->set_value(fn(c));
          }
        } catch (...) {
          promise->set_exception(std::current_exception());
        }
      },
      [promise](Response res) {
        try {
          promise->set_exception(std::make_exception_ptr(
              std::runtime_error("catalog call failed: " + std::to_string(res.result_int()))));
        } catch (const std::future_error&) {
          // already answered
        }
      });
  while (future.wait_for(std::chrono::milliseconds(200)) != std::future_status::ready)
    if (stopping)
      throw HubUnreachable("stopping");
  return future.get();
}

}  // namespace

void HubPusher::run() {
  spdlog::info("hub: pushing to {}", hub_.url());
  int failures = 0;
  while (!stopping_) {
    bool busy = false;
    try {
      busy = pass();
      {
        std::lock_guard lock(statusMutex_);
        tokenRefused_.clear();
        tlsFailed_.clear();
      }
      if (failures > 0)
        spdlog::info("hub: reachable again after {} failure(s)", failures);
      failures = 0;
    } catch (const HubTokenRefused& e) {
      if (stopping_)
        break;
      if (tokenRefused().empty())
        spdlog::error("hub: {} (is [hub] token this station's token at the hub?)", e.what());
      {
        std::lock_guard lock(statusMutex_);
        tokenRefused_ = e.what();
      }
      ++counters_.failures;
      failures = 1000;  // the longest backoff: a wrong token does not fix itself quickly
    } catch (const HubTlsFailed& e) {
      if (stopping_)
        break;
      // Logged when it starts or changes, and then every 10th time like other failures.
      ++failures;
      ++counters_.failures;
      bool changed = false;
      {
        std::lock_guard lock(statusMutex_);
        changed = tlsFailed_ != e.what();
        tlsFailed_ = e.what();
      }
      if (changed || failures % 10 == 0)
        spdlog::error("hub: {} (failure {}, next try in {} ms)", e.what(), failures,
                      hubBackoff(failures).count());
    } catch (const std::exception& e) {
      if (stopping_)
        break;
      ++failures;
      ++counters_.failures;
      if (failures == 1 || failures % 10 == 0)
        spdlog::warn("hub: {} (failure {}, next try in {} ms)", e.what(), failures,
                     hubBackoff(failures).count());
    }
    if (busy && failures == 0)
      continue;
    std::unique_lock lock(mutex_);
    wake_.wait_for(lock, failures > 0 ? hubBackoff(failures) : poll_,
                   [&] { return stopping_.load(); });
  }
}

void HubPusher::park(const OutboxEntry& row, const std::pair<int, std::string>& refusal) {
  spdlog::error("hub: outbox row {} (item {}) refused for good, parked: {}", row.seq, row.itemId,
                refusal.second);
  onCatalog<bool>(station_, stopping_, [seq = row.seq, refusal](Catalog& c) {
    return c.refuseOutbox(seq, refusal.first, refusal.second);
  });
  ++counters_.refused;
}

std::string HubPusher::tlsFailed() const {
  std::lock_guard lock(statusMutex_);
  return tlsFailed_;
}

std::string HubPusher::tokenRefused() const {
  std::lock_guard lock(statusMutex_);
  return tokenRefused_;
}

nlohmann::json HubPusher::status() const {
  const std::string token = tokenRefused();
  const std::string tls = tlsFailed();
  return {{"url", hub_.url()},
          {"pushed", counters_.pushed.load()},
          {"blobs_sent", counters_.blobsSent.load()},
          {"changes_applied", counters_.changesApplied.load()},
          {"failures", counters_.failures.load()},
          {"refused_this_run", counters_.refused.load()},
          {"token_refused", token.empty() ? nlohmann::json(nullptr) : nlohmann::json(token)},
          {"tls_error", tls.empty() ? nlohmann::json(nullptr) : nlohmann::json(tls)}};
}

bool HubPusher::pass() {
  const auto rows = onCatalog<std::vector<OutboxEntry>>(
      station_, stopping_, [](Catalog& c) { return c.outbox(kBatch); });
  for (const auto& row : rows) {
    if (stopping_)
      return false;
    const auto item = onCatalog<std::optional<Item>>(
        station_, stopping_, [id = row.itemId](Catalog& c) { return c.item(id, true); });
    // Set when the hub refused this row for good: it is parked, and the next row goes.
    std::optional<std::pair<int, std::string>> refusal;
    if (item) {
      nlohmann::json doc = item->toJson();
      // The size guide goes with the item: the hub's shop exports show it as the station's do.
      const auto guide = onCatalog<std::optional<nlohmann::json>>(
          station_, stopping_, [id = row.itemId](Catalog& c) { return c.sizeGuide(id); });
      doc["size_guide"] = guide ? *guide : nlohmann::json(nullptr);
      nlohmann::json images = nlohmann::json::object();
      for (const auto& im : item->images) {
        const std::string target = "/api/hub/blobs/" + im.sha256;
        const auto head = call(hub_, tls_.get(), token_, http::verb::head, target);
        if (head.status == 404) {
          auto bytes = station_.store().read(im.sha256);
          if (!bytes) {
            // Nothing can bring it back: the item goes without it rather than never.
            spdlog::error(
                "hub: item {}: image '{}' ({}) is missing from the store; pushed "
                "without it",
                item->id, im.kind, im.sha256);
            continue;
          }
          const auto put = call(hub_, tls_.get(), token_, http::verb::put, target,
                                std::move(*bytes), "application/octet-stream");
          if (!ok(put)) {
            refusal = checkRefusal("PUT " + target, put);
            break;
          }
          ++counters_.blobsSent;
        } else if (!ok(head)) {
          if (hubRefusesToken(head.status))
            throw HubTokenRefused(describe("HEAD " + target, head));
          throw HubUnreachable("HEAD " + target + ": " + std::to_string(head.status));
        }
        images[im.kind] = {{"sha256", im.sha256}, {"media_type", im.mediaType}};
      }
      if (refusal) {
        park(row, *refusal);
        continue;
      }
      doc["images"] = images;
      // The patterns go beside the item (not in its JSON, which the hub lists): the hub writes
      // its pattern files and catalog.zip from them. An empty object says "none", which the
      // hub stores as none.
      const auto patterns = onCatalog<std::map<std::string, nlohmann::json>>(
          station_, stopping_, [id = row.itemId, sizes = item->sizes](Catalog& c) {
            std::map<std::string, nlohmann::json> out;
            for (const auto& size : sizes)
              if (auto p = c.pattern(id, size))
                out[size] = std::move(*p);
            return out;
          });
      const nlohmann::json body{{"local_id", item->id},
                                {"item", doc},
                                {"deleted", item->deletedAt.has_value()},
                                {"patterns", patterns}};
      const auto res = call(hub_, tls_.get(), token_, http::verb::post, "/api/hub/push",
                            body.dump(), "application/json");
      if (!ok(res)) {
        refusal = checkRefusal("push of item " + std::to_string(item->id), res);
        park(row, *refusal);
        continue;
      }
      ++counters_.pushed;
    }
    onCatalog<bool>(station_, stopping_,
                    [seq = row.seq](Catalog& c) { return c.removeOutbox(seq); });
  }

  // The hub's edits of this station's items, after the cursor kept in the catalog.
  const auto cursor = onCatalog<std::string>(
      station_, stopping_, [](Catalog& c) { return c.hubState("changes_cursor").value_or("0"); });
  const auto res =
      call(hub_, tls_.get(), token_, http::verb::get, "/api/hub/changes?since=" + cursor);
  if (hubRefusesToken(res.status))
    throw HubTokenRefused(describe("changes", res));
  if (!ok(res))
    throw HubUnreachable("changes: " + std::to_string(res.status) + " " + res.body.substr(0, 200));
  const auto j = nlohmann::json::parse(res.body, nullptr, false);
  if (j.is_discarded() || !j.contains("changes") || !j["changes"].is_array() ||
      !j.contains("next") || !j["next"].is_number_integer())
    throw HubUnreachable("changes: the hub's answer is not {\"changes\": [...], \"next\": N}");
  const auto& changes = j["changes"];
  for (const auto& ch : changes) {
    if (!ch.is_object() || !ch.contains("local_id") || !ch["local_id"].is_number_integer() ||
        !ch.contains("title") || !ch["title"].is_string() || !ch.contains("status") ||
        !ch["status"].is_string())
      throw HubUnreachable("changes: malformed change " + ch.dump().substr(0, 200));
    HubEdit edit;
    edit.title = ch["title"].get<std::string>();
    edit.status = ch["status"].get<std::string>();
    if (ch.contains("price_cents") && ch["price_cents"].is_number_integer())
      edit.priceCents = std::optional<std::int64_t>(ch["price_cents"].get<std::int64_t>());
    else
      edit.priceCents = std::optional<std::int64_t>();
    const auto localId = ch["local_id"].get<std::int64_t>();
    const bool applied = onCatalog<bool>(
        station_, stopping_, [localId, edit](Catalog& c) { return c.applyHubEdit(localId, edit); });
    if (applied)
      ++counters_.changesApplied;
  }
  const std::string next = std::to_string(j["next"].get<std::int64_t>());
  if (next != cursor)
    onCatalog<void>(station_, stopping_,
                    [next](Catalog& c) { c.setHubState("changes_cursor", next); });
  return rows.size() == static_cast<std::size_t>(kBatch) || !changes.empty();
}

}  // namespace garmcap::daemon
