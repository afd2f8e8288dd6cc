#pragma once
// Who calls the hub (a station by its token, the admin, or nobody) and which stations a read
// covers: shared by the hub's API routes (hub_service.cpp) and its exports (hub_exports.cpp).

#include <optional>
#include <string>

#include "garmcap/daemon/http_router.h"
#include "garmcap/hub/hub_config.h"
#include "garmcap/hub/hub_store.h"

namespace garmcap::hub {

struct Caller {
  std::optional<std::string> station;
  bool admin = false;
  bool any() const { return admin || station.has_value(); }
};

class HubLogins;  // hub_web_routes.h

/// The caller of `req` by its `Authorization: Bearer` token (RFC 7235: the scheme in any case)
/// or, without one and given `logins`, by its browser session cookie.
Caller callerOf(const daemon::Request& req, HubStore& store, const HubConfig& config,
                const HubLogins* logins = nullptr);

/// 401 with the hub's WWW-Authenticate challenge.
daemon::Response unauthorized(const std::string& what);

/// The station a read covers: for the admin the `station` query ("" or absent: every station),
/// for a station token its own station. Throws BadRequest for a malformed station name; nullopt
/// when a station token asks for another station's (the route answers 403).
std::optional<std::string> readScope(const Caller& caller, const daemon::RouteMatch& m);

/// The item `{id}` of the route if the caller of `req` may read it (admin: any; a station: its
/// own) and it is not deleted. Otherwise replies (401 without a caller, 404 for an item absent,
/// deleted or another station's, so its ids tell nothing) and returns nullopt.
std::optional<HubItem> readableItem(const daemon::Request& req, const daemon::RouteMatch& m,
                                    HubStore& store, const HubConfig& config,
                                    const HubLogins* logins, const daemon::Reply& reply);

}  // namespace garmcap::hub
