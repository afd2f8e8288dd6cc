#include "garmcap/hub/hub_service.h"

#include <spdlog/spdlog.h>

#include <boost/asio/executor_work_guard.hpp>
#include <charconv>

#include "garmcap/daemon/content_store.h"
#include "garmcap/daemon/http_server.h"
#include "garmcap/daemon/login_sessions.h"
#include "garmcap/daemon/tls_context.h"
#include "garmcap/daemon/utf8.h"
#include "garmcap/hub/hub_caller.h"
#include "garmcap/hub/hub_exports.h"
#include "garmcap/hub/hub_graded_routes.h"
#include "garmcap/hub/hub_pattern_routes.h"
#include "garmcap/hub/hub_web_routes.h"

namespace garmcap::hub {

namespace http = daemon::http;
using daemon::BadRequest;
using daemon::jsonError;
using daemon::jsonResponse;
using daemon::Reply;
using daemon::Request;
using daemon::RouteMatch;

namespace {

std::int64_t queryInt(const RouteMatch& m, const std::string& name, std::int64_t fallback,
                      std::int64_t lo, std::int64_t hi) {
  const auto v = m.queryValue(name);
  if (!v || v->empty())
    return fallback;
  std::int64_t x = 0;
  const auto [end, ec] = std::from_chars(v->data(), v->data() + v->size(), x);
  if (ec != std::errc() || end != v->data() + v->size() || x < lo || x > hi)
    throw BadRequest(name + " must be an integer " + std::to_string(lo) + ".." +
                     std::to_string(hi) + ", got '" + daemon::quoteInput(*v) + "'");
  return x;
}

std::string stringField(const nlohmann::json& j, const char* name, bool required = false) {
  if (!j.contains(name) || j[name].is_null()) {
    if (required)
      throw BadRequest(std::string("item.") + name + " is required");
    return "";
  }
  if (!j[name].is_string())
    throw BadRequest(std::string("item.") + name + " must be a string");
  return j[name].get<std::string>();
}

std::optional<std::int64_t> priceField(const nlohmann::json& j, const std::string& where) {
  if (!j.contains("price_cents") || j["price_cents"].is_null())
    return std::nullopt;
  if (!j["price_cents"].is_number_integer() || j["price_cents"].get<std::int64_t>() < 0)
    throw BadRequest(where + "price_cents must be a non-negative integer or null");
  return j["price_cents"].get<std::int64_t>();
}

// The push body: {"local_id": N, "item": <the station's item JSON>, "deleted": bool}.
PushedItem parsePush(const nlohmann::json& body) {
  if (!body.is_object())
    throw BadRequest("body must be an object {\"local_id\", \"item\", \"deleted\"}");
  PushedItem p;
  if (!body.contains("local_id") || !body["local_id"].is_number_integer() ||
      body["local_id"].get<std::int64_t>() <= 0)
    throw BadRequest("local_id must be a positive integer");
  p.localId = body["local_id"].get<std::int64_t>();
  if (body.contains("deleted")) {
    if (!body["deleted"].is_boolean())
      throw BadRequest("deleted must be true or false");
    p.deleted = body["deleted"].get<bool>();
  }
  if (!body.contains("item") || !body["item"].is_object())
    throw BadRequest("item must be an object (the station's item JSON)");
  const auto& item = body["item"];
  p.sku = stringField(item, "sku");
  p.title = stringField(item, "title");
  p.status = stringField(item, "status", true);
  if (p.status != "needs_review" && p.status != "approved" && p.status != "rejected")
    throw BadRequest("item.status must be needs_review, approved or rejected, got '" +
                     daemon::quoteInput(p.status) + "'");
  p.type = stringField(item, "type");
  p.priceCents = priceField(item, "item.");
  if (item.contains("measurements")) {
    if (!item["measurements"].is_object())
      throw BadRequest("item.measurements must be an object of name -> cm");
    for (const auto& [name, v] : item["measurements"].items()) {
      if (!v.is_number())
        throw BadRequest("item.measurements." + daemon::quoteInput(name) + " must be a number");
      p.measurementsCm[name] = v.get<double>();
    }
  }
  if (item.contains("images")) {
    if (!item["images"].is_object())
      throw BadRequest("item.images must be an object of kind -> {sha256, media_type}");
    for (const auto& [kind, v] : item["images"].items()) {
      if (!v.is_object() || !v.contains("sha256") || !v["sha256"].is_string() ||
          !daemon::isSha256Hex(v["sha256"].get<std::string>()))
        throw BadRequest("item.images." + daemon::quoteInput(kind) +
                         ".sha256 must be 64 lower-case hex digits");
      const std::string media = v.contains("media_type") && v["media_type"].is_string()
                                    ? v["media_type"].get<std::string>()
                                    : "application/octet-stream";
      p.images.push_back({kind, v["sha256"].get<std::string>(), media});
    }
  }
  p.doc = item;
  p.patterns = pushedPatterns(body);
  return p;
}

const std::string& shaParam(const RouteMatch& m) {
  const auto& sha = m.param("sha");
  if (!daemon::isSha256Hex(sha))
    throw BadRequest("a blob is named by its sha256: 64 lower-case hex digits");
  return sha;
}

}  // namespace

Caller callerOf(const Request& req, HubStore& store, const HubConfig& config,
                const HubLogins* logins) {
  Caller c;
  const auto auth = req[http::field::authorization];
  std::string_view a(auth.data(), auth.size());
  if (a.empty() && logins)
    return sessionCaller(req, *logins);
  // RFC 7235: the scheme is case-insensitive, one or more spaces follow.
  if (a.size() <= 7 || !boost::beast::iequals(boost::beast::string_view(a.data(), 6), "Bearer") ||
      a[6] != ' ')
    return c;
  a.remove_prefix(7);
  while (!a.empty() && a.front() == ' ')
    a.remove_prefix(1);
  if (a.empty())
    return c;
  const std::string hash = tokenHash(std::string(a));
  if (!config.adminTokenSha256.empty() && daemon::constantTimeEqual(hash, config.adminTokenSha256))
    c.admin = true;
  else
    c.station = store.stationForToken(hash);
  return c;
}

daemon::Response unauthorized(const std::string& what) {
  auto res = jsonError(http::status::unauthorized, what);
  res.set(http::field::www_authenticate, "Bearer realm=\"garmcap-hub\"");
  return res;
}

std::optional<std::string> readScope(const Caller& c, const RouteMatch& m) {
  std::string station;
  if (auto s = m.queryValue("station")) {
    if (!s->empty() && !validStationId(*s))
      throw BadRequest("station must be 1..64 of [A-Za-z0-9_-]");
    station = *s;
  }
  if (c.admin)
    return station;
  if (!station.empty() && station != *c.station)
    return std::nullopt;
  return *c.station;
}

std::optional<HubItem> readableItem(const Request& req, const RouteMatch& m, HubStore& store,
                                    const HubConfig& config, const HubLogins* logins,
                                    const Reply& reply) {
  const Caller c = callerOf(req, store, config, logins);
  if (!c.any()) {
    reply(unauthorized("a station or admin token is required"));
    return std::nullopt;
  }
  const auto id = m.id("id");
  auto it = store.item(id);
  if (!it || it->deletedAt || (!c.admin && it->station != *c.station)) {
    reply(jsonError(http::status::not_found, "no item " + std::to_string(id)));
    return std::nullopt;
  }
  return it;
}

void addHubRoutes(daemon::Router& router, HubStore& store, const HubConfig& config,
                  HubLogins* logins) {
  auto who = [&store, &config, logins](const Request& req) {
    return callerOf(req, store, config, logins);
  };

  router.add(
      http::verb::get, "/api/hub/health", [&store](const Request&, const RouteMatch&, Reply reply) {
        reply(jsonResponse(http::status::ok, {{"ok", true}, {"schema", store.schemaVersion()}}));
      });

  // What the hub requires, in the fields of the station's /api/session: a bearer token on every
  // request (a station's or the admin's), or the session cookie a browser gets for one (POST
  // and DELETE, hub_web_routes.cpp; "login" says whether they are there).
  router.add(http::verb::get, "/api/session",
             [who, logins](const Request& req, const RouteMatch&, Reply reply) {
               const Caller c = who(req);
               nlohmann::json body{{"authenticated", c.any()},
                                   {"token_required", true},
                                   {"login", logins != nullptr},
                                   {"role", c.admin     ? nlohmann::json("admin")
                                            : c.station ? nlohmann::json("station")
                                                        : nlohmann::json(nullptr)}};
               body["station"] = c.station ? nlohmann::json(*c.station) : nlohmann::json(nullptr);
               reply(jsonResponse(http::status::ok, body));
             });

  router.add(http::verb::post, "/api/hub/push",
             [&store, who](const Request& req, const RouteMatch&, Reply reply) {
               const Caller c = who(req);
               if (!c.station)
                 return reply(unauthorized("a station token is required to push"));
               const PushedItem item = parsePush(daemon::parseJsonBody(req));
               try {
                 const PushOutcome out = store.push(*c.station, item);
                 reply(jsonResponse(
                     http::status::ok,
                     {{"id", out.hubId}, {"created", out.created}, {"hub_kept", out.hubKept}}));
               } catch (const HubStoreError& e) {
                 reply(jsonError(http::status::conflict, e.what()));
               }
             });

  // HEAD before GET: the router would answer a HEAD with the GET route, reading the blob.
  router.add(http::verb::head, "/api/hub/blobs/{sha}",
             [&store, who](const Request& req, const RouteMatch& m, Reply reply) {
               if (!who(req).any())
                 return reply(unauthorized("a station or admin token is required"));
               const auto& sha = shaParam(m);
               reply(store.hasBlob(sha)
                         ? daemon::textResponse(http::status::ok, "application/octet-stream", "")
                         : jsonError(http::status::not_found, "no such blob"));
             });
  router.add(http::verb::get, "/api/hub/blobs/{sha}",
             [&store, who](const Request& req, const RouteMatch& m, Reply reply) {
               const Caller c = who(req);
               if (!c.any())
                 return reply(unauthorized("a station or admin token is required"));
               // A station reads only the blobs of its own items (HEAD stays open to every
               // token: the pusher asks before it sends, and learns only about a hash it has).
               if (!c.admin && !store.blobOfStation(shaParam(m), *c.station))
                 return reply(jsonError(http::status::not_found, "no such blob"));
               auto bytes = store.blob(shaParam(m));
               if (!bytes)
                 return reply(jsonError(http::status::not_found, "no such blob"));
               reply(daemon::textResponse(http::status::ok, "application/octet-stream",
                                          std::move(*bytes)));
             });
  router.add(http::verb::put, "/api/hub/blobs/{sha}",
             [&store, who](const Request& req, const RouteMatch& m, Reply reply) {
               if (!who(req).station)
                 return reply(unauthorized("a station token is required to send blobs"));
               const auto& sha = shaParam(m);
               const std::string actual = daemon::sha256Hex(req.body());
               if (actual != sha)
                 return reply(jsonError(http::status::bad_request,
                                        "the body's sha256 is " + actual + ", not " + sha));
               const bool had = store.hasBlob(sha);
               if (!had)
                 store.putBlob(sha, req.body());
               reply(jsonResponse(had ? http::status::ok : http::status::created,
                                  {{"sha256", sha}, {"bytes", req.body().size()}}));
             });

  router.add(http::verb::get, "/api/hub/changes",
             [&store, who](const Request& req, const RouteMatch& m, Reply reply) {
               const Caller c = who(req);
               if (!c.station)
                 return reply(unauthorized("a station token is required"));
               const auto since =
                   queryInt(m, "since", 0, 0, std::numeric_limits<std::int64_t>::max());
               const auto limit = queryInt(m, "limit", 100, 1, 1000);
               nlohmann::json list = nlohmann::json::array();
               std::int64_t next = since;
               for (const auto& ch : store.changes(*c.station, since, static_cast<int>(limit))) {
                 list.push_back(ch.toJson());
                 next = ch.seq;
               }
               reply(jsonResponse(http::status::ok, {{"changes", list}, {"next", next}}));
             });

  router.add(http::verb::get, "/api/items",
             [&store, who](const Request& req, const RouteMatch& m, Reply reply) {
               const Caller c = who(req);
               if (!c.any())
                 return reply(unauthorized("a station or admin token is required"));
               HubQuery q;
               // A station token lists its own station's items only; the admin token all.
               const auto scope = readScope(c, m);
               if (!scope)
                 return reply(jsonError(http::status::forbidden,
                                        "a station token lists only its own station's items; "
                                        "the admin token lists every station's"));
               q.station = *scope;
               if (auto s = m.queryValue("status")) {
                 if (!s->empty() && *s != "needs_review" && *s != "approved" && *s != "rejected")
                   throw BadRequest("status must be needs_review, approved or rejected, got '" +
                                    daemon::quoteInput(*s) + "'");
                 q.status = *s;
               }
               if (auto s = m.queryValue("q"))
                 q.search = s->substr(0, 200);
               q.afterId = queryInt(m, "after", 0, 0, std::numeric_limits<std::int64_t>::max());
               q.limit = static_cast<int>(queryInt(m, "limit", 50, 1, 500));
               const HubPage page = store.list(q);
               nlohmann::json items = nlohmann::json::array();
               for (const auto& it : page.items)
                 items.push_back(it.toJson());
               nlohmann::json body{{"items", items}};
               body["next"] = page.next ? nlohmann::json(*page.next) : nlohmann::json(nullptr);
               reply(jsonResponse(http::status::ok, body));
             });

  router.add(http::verb::get, "/api/items/{id}",
             [&store, who](const Request& req, const RouteMatch& m, Reply reply) {
               const Caller c = who(req);
               if (!c.any())
                 return reply(unauthorized("a station or admin token is required"));
               const auto id = m.id("id");
               auto it = store.item(id);
               // Another station's item is answered as absent, so its ids tell nothing.
               if (!it || (!c.admin && it->station != *c.station))
                 return reply(jsonError(http::status::not_found, "no item " + std::to_string(id)));
               reply(jsonResponse(http::status::ok, it->toJson()));
             });

  router.add(http::verb::patch, "/api/items/{id}",
             [&store, who](const Request& req, const RouteMatch& m, Reply reply) {
               if (!who(req).admin)
                 return reply(unauthorized("the admin token is required to edit at the hub"));
               const auto id = m.id("id");
               const auto body = daemon::parseJsonBody(req);
               if (!body.is_object())
                 throw BadRequest("body must be an object of title, price_cents, status");
               HubPatch p;
               for (const auto& [key, v] : body.items()) {
                 if (key == "title") {
                   if (!v.is_string())
                     throw BadRequest("title must be a string");
                   p.title = v.get<std::string>();
                 } else if (key == "status") {
                   if (!v.is_string())
                     throw BadRequest("status must be a string");
                   p.status = v.get<std::string>();
                 } else if (key == "price_cents") {
                   p.priceCents = priceField(body, "");
                 } else {
                   throw BadRequest("the hub edits title, price_cents and status only, not '" +
                                    daemon::quoteInput(key) + "'");
                 }
               }
               PatchResult r;
               try {
                 r = store.patch(id, p);
               } catch (const HubStoreError& e) {
                 throw BadRequest(e.what());
               }
               if (r == PatchResult::kNotFound)
                 return reply(jsonError(http::status::not_found, "no item " + std::to_string(id)));
               if (r == PatchResult::kStationOwned)
                 return reply(jsonError(http::status::conflict,
                                        "the station owns this item until it is approved: "
                                        "approve it (status \"approved\") to edit it here"));
               reply(jsonResponse(http::status::ok, store.item(id)->toJson()));
             });

  addHubExportRoutes(router, store, config, logins);
  addHubPatternRoutes(router, store, config, logins);
  addHubGradedRoutes(router, store, config, logins);
}

HubService::HubService(const HubConfig& config) : config_(config) {
  config_.validate();
  store_ = std::make_unique<HubStore>(config_.databaseUrl, config_.connections);
  store_->setStations(config_.stationTokenSha256);
  addHubRoutes(router_, *store_, config_, &logins_);
  addHubWebRoutes(router_, *store_, config_, logins_);
  // The review UI (daemon/hub/web/ with the station's common.js and app.css) at "/".
  files_ = std::make_unique<daemon::StaticFiles>(config_.webDir);
}

HubService::~HubService() {
  stop();
}

void HubService::start() {
  daemon::Config http;
  http.listenAddress = config_.listenAddress;
  http.listenPort = config_.listenPort;
  http.bodyLimitBytes = config_.bodyLimitBytes;
  http.requestTimeoutS = config_.requestTimeoutS;
  http.minSendRate = config_.minSendRate;
  http.token = "";  // every route checks its caller itself (station or admin token)
  std::shared_ptr<boost::asio::ssl::context> tls;
  if (config_.tls())
    tls = daemon::makeServerTlsContext(config_.tlsCertFile, config_.tlsKeyFile);
  server_ = std::make_unique<daemon::HttpServer>(io_, http, router_, *files_, std::move(tls));
  server_->start();
  for (int i = 0; i < config_.threads; ++i)
    threads_.emplace_back([this] {
      auto guard = boost::asio::make_work_guard(io_);
      io_.run();
    });
}

void HubService::stop() {
  if (server_)
    server_->stop();
  io_.stop();
  for (auto& t : threads_)
    if (t.joinable())
      t.join();
  threads_.clear();
}

std::uint16_t HubService::port() const {
  return server_ ? server_->port() : 0;
}

}  // namespace garmcap::hub
