#pragma once
// Registers the station's JSON API (docs/api.md) on a router. Route modules of other owners
// (GARMCAP_ROUTE_MODULE) are added after these, so a literal route here wins over a pattern there.

#include <nlohmann/json.hpp>
#include <string>

#include "garmcap/daemon/http_router.h"
#include "garmcap/daemon/station.h"

namespace garmcap::daemon {

void addApiRoutes(Router& router, Station& station);

/// The size guide as CSV: "measurement,<size>,<size>..." then one row per measurement (cm, one
/// decimal). Throws nlohmann::json exceptions on a malformed guide.
std::string sizeGuideCsv(const nlohmann::json& guide);

}  // namespace garmcap::daemon
