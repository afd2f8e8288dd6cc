#include "garmcap/hub/hub_web_routes.h"

#include <spdlog/spdlog.h>

#include <vector>

namespace garmcap::hub {

namespace http = daemon::http;
using daemon::BadRequest;
using daemon::jsonError;
using daemon::jsonResponse;
using daemon::Reply;
using daemon::Request;
using daemon::RouteMatch;

std::string HubLogins::create(const Caller& caller) {
  const std::string id = ids_.create();
  std::lock_guard lock(mutex_);
  // Sessions that expired or gave way to newer ones leave the map here, so it stays as small as
  // the live sessions (at most LoginSessions' maximum, plus this one).
  std::erase_if(callers_, [this](const auto& entry) { return !ids_.valid(entry.first); });
  callers_[id] = caller;
  return id;
}

std::optional<Caller> HubLogins::caller(std::string_view id) const {
  if (!ids_.valid(id))
    return std::nullopt;
  std::lock_guard lock(mutex_);
  const auto it = callers_.find(id);
  if (it == callers_.end())
    return std::nullopt;
  return it->second;
}

void HubLogins::revoke(std::string_view id) {
  ids_.revoke(id);
  std::lock_guard lock(mutex_);
  if (const auto it = callers_.find(id); it != callers_.end())
    callers_.erase(it);
}

Caller sessionCaller(const Request& req, const HubLogins& logins) {
  const auto header = req[http::field::cookie];
  const auto id =
      daemon::cookieValue(std::string_view(header.data(), header.size()), daemon::kSessionCookie);
  if (!id)
    return {};
  return logins.caller(*id).value_or(Caller{});
}

namespace {

nlohmann::json sessionBody(const Caller& c) {
  nlohmann::json body{{"authenticated", c.any()},
                      {"token_required", true},
                      {"login", true},
                      {"role", c.admin     ? nlohmann::json("admin")
                               : c.station ? nlohmann::json("station")
                                           : nlohmann::json(nullptr)}};
  body["station"] = c.station ? nlohmann::json(*c.station) : nlohmann::json(nullptr);
  return body;
}

}  // namespace

void addHubWebRoutes(daemon::Router& router, HubStore& store, const HubConfig& config,
                     HubLogins& logins) {
  // The cookie's attributes: the station's, and Secure when the hub serves HTTPS (off loopback
  // it must), so the session id never goes out in clear.
  const std::string attributes =
      std::string("; Path=/; HttpOnly; SameSite=Strict") + (config.tls() ? "; Secure" : "");
  auto cookie = [attributes](const std::string& value, long long maxAge) {
    return std::string(daemon::kSessionCookie) + "=" + value + attributes +
           "; Max-Age=" + std::to_string(maxAge);
  };

  router.add(
      http::verb::post, "/api/session",
      [&store, &config, &logins, cookie](const Request& req, const RouteMatch&, Reply reply) {
        const auto body = daemon::parseJsonBody(req);
        if (!body.is_object() || body.size() != 1 || !body.contains("token") ||
            !body["token"].is_string())
          throw BadRequest(R"(body must be {"token": "..."})");
        const std::string hash = tokenHash(body["token"].get<std::string>());
        Caller c;
        if (!config.adminTokenSha256.empty() &&
            daemon::constantTimeEqual(hash, config.adminTokenSha256))
          c.admin = true;
        else
          c.station = store.stationForToken(hash);
        if (!c.any()) {
          spdlog::warn("hub: a log-in with a token that is neither the admin's nor a station's");
          return reply(unauthorized("wrong token"));
        }
        auto res = jsonResponse(http::status::ok, sessionBody(c));
        res.set(http::field::set_cookie, cookie(logins.create(c), logins.lifetime().count()));
        reply(std::move(res));
      });

  router.add(http::verb::delete_, "/api/session",
             [&logins, cookie](const Request& req, const RouteMatch&, Reply reply) {
               const auto header = req[http::field::cookie];
               if (const auto id = daemon::cookieValue(
                       std::string_view(header.data(), header.size()), daemon::kSessionCookie))
                 logins.revoke(*id);
               auto res = jsonResponse(http::status::ok, sessionBody(Caller{}));
               res.set(http::field::set_cookie, cookie("", 0));
               reply(std::move(res));
             });

  router.add(http::verb::get, "/api/hub/stations",
             [&store, &config, &logins](const Request& req, const RouteMatch&, Reply reply) {
               Caller c = callerOf(req, store, config, &logins);
               if (!c.any())
                 return reply(unauthorized("a station or admin token is required"));
               nlohmann::json list = nlohmann::json::array();
               for (const auto& s : store.stations())
                 if (c.admin || s.id == *c.station) {
                   // Every status, 0 for one the station has none of.
                   nlohmann::json statuses{{"needs_review", 0}, {"approved", 0}, {"rejected", 0}};
                   for (const auto& [status, n] : s.byStatus)
                     statuses[status] = n;
                   list.push_back({{"id", s.id}, {"items", s.items}, {"statuses", statuses}});
                 }
               reply(jsonResponse(http::status::ok, {{"stations", list}}));
             });
}

}  // namespace garmcap::hub
