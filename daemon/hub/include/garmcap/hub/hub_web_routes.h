#pragma once
// The hub's web UI (daemon/hub/web/, served as static files at "/") and what it needs beyond the
// API: a browser log-in and the list of stations for its filter.
//
//   POST   /api/session      {"token": "..."}: a station's or the admin token for an HttpOnly,
//                            SameSite=Strict session cookie (Secure over TLS); 401 for a wrong one
//   DELETE /api/session      logs out (revokes the cookie's session)
//   GET    /api/hub/stations admin: every station the hub knows, with its live item count;
//                            a station: itself only
//
// A browser cannot put an Authorization header on an <img> (the photos are blobs at the hub),
// so the UI trades its token once for a cookie, as at the station (login_sessions.h). The cookie
// stands for the caller the token named (admin or one station) and gives exactly its rights;
// sessions live in memory, a restart asks for the token again. Writes stay JSON-only and
// same-origin (the request guard), and the cookie is SameSite=Strict.

#include <chrono>
#include <map>
#include <mutex>
#include <optional>
#include <string>

#include "garmcap/daemon/http_router.h"
#include "garmcap/daemon/login_sessions.h"
#include "garmcap/hub/hub_caller.h"
#include "garmcap/hub/hub_config.h"
#include "garmcap/hub/hub_store.h"

namespace garmcap::hub {

/// Browser sessions, each for the caller whose token opened it.
class HubLogins {
 public:
  /// A new session id for `caller` (who must be someone).
  std::string create(const Caller& caller);
  /// The caller of a live session id.
  std::optional<Caller> caller(std::string_view id) const;
  void revoke(std::string_view id);
  std::chrono::seconds lifetime() const { return ids_.lifetime(); }

 private:
  daemon::LoginSessions ids_;  // random ids, expiry, the oldest evicted past its maximum
  mutable std::mutex mutex_;
  std::map<std::string, Caller, std::less<>> callers_;
};

/// The caller of the request's session cookie, or nobody.
Caller sessionCaller(const daemon::Request& req, const HubLogins& logins);

/// Adds the routes above; everything outlives the router.
void addHubWebRoutes(daemon::Router& router, HubStore& store, const HubConfig& config,
                     HubLogins& logins);

}  // namespace garmcap::hub
