#include "garmcap/daemon/hub_pusher.h"

#include <spdlog/spdlog.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <future>
#include <stdexcept>

#include "garmcap/daemon/catalog.h"
#include "garmcap/daemon/content_store.h"

namespace garmcap::daemon {

namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;

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

struct HubReply {
  int status = 0;
  std::string body;
};

// One request on a fresh connection (the hub may restart between any two).
HubReply call(const HubAddress& hub, const std::string& token, http::verb verb,
              const std::string& target, std::string body = {},
              const std::string& contentType = {}) {
  asio::io_context io;
  asio::ip::tcp::resolver resolver(io);
  beast::tcp_stream stream(io);
  beast::error_code ec;
  const auto endpoints = resolver.resolve(hub.host, std::to_string(hub.port), ec);
  if (ec)
    throw HubUnreachable("cannot resolve " + hub.host + ": " + ec.message());
  stream.expires_after(kHttpTimeout);
  stream.connect(endpoints, ec);
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
  http::write(stream, req, ec);
  if (ec)
    throw HubUnreachable(target + ": " + ec.message());
  beast::flat_buffer buffer;
  http::response_parser<http::string_body> parser;
  parser.body_limit(16u << 20);
  if (verb == http::verb::head)
    parser.skip(true);
  http::read(stream, buffer, parser, ec);
  if (ec)
    throw HubUnreachable(target + ": " + ec.message());
  stream.socket().shutdown(asio::ip::tcp::socket::shutdown_both, ec);
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
    throw ConfigError("[hub] url: not http://HOST:PORT: '" + config.hubUrl + "'");
  hub_ = *hub;
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
  spdlog::info("hub: pushing to http://{}:{}", hub_.host, hub_.port);
  int failures = 0;
  while (!stopping_) {
    bool busy = false;
    try {
      busy = pass();
      {
        std::lock_guard lock(statusMutex_);
        tokenRefused_.clear();
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

std::string HubPusher::tokenRefused() const {
  std::lock_guard lock(statusMutex_);
  return tokenRefused_;
}

nlohmann::json HubPusher::status() const {
  const std::string token = tokenRefused();
  return {{"url", "http://" + hub_.host + ":" + std::to_string(hub_.port)},
          {"pushed", counters_.pushed.load()},
          {"blobs_sent", counters_.blobsSent.load()},
          {"changes_applied", counters_.changesApplied.load()},
          {"failures", counters_.failures.load()},
          {"refused_this_run", counters_.refused.load()},
          {"token_refused", token.empty() ? nlohmann::json(nullptr) : nlohmann::json(token)}};
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
      nlohmann::json images = nlohmann::json::object();
      for (const auto& im : item->images) {
        const std::string target = "/api/hub/blobs/" + im.sha256;
        const auto head = call(hub_, token_, http::verb::head, target);
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
          const auto put = call(hub_, token_, http::verb::put, target, std::move(*bytes),
                                "application/octet-stream");
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
      const nlohmann::json body{
          {"local_id", item->id}, {"item", doc}, {"deleted", item->deletedAt.has_value()}};
      const auto res =
          call(hub_, token_, http::verb::post, "/api/hub/push", body.dump(), "application/json");
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
  const auto res = call(hub_, token_, http::verb::get, "/api/hub/changes?since=" + cursor);
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
