#pragma once
// The station's routes, one resource a file, each added by a named function, and all of them
// registered from one place in a fixed order (as Beast's examples hand a request to a plain
// function): no static initialiser decides what a daemon serves or in which order.

#include "garmcap/daemon/http_router.h"

namespace garmcap::daemon {

class Station;

/// POST /api/items/review: approve or reject many items at once (review_routes.cpp).
void addReviewRoutes(Router& router, RouteContext& ctx);
/// GET/PUT /api/settings/shop: the shop's setup (settings_routes.cpp).
void addSettingsRoutes(Router& router, RouteContext& ctx);
/// /api/tape: the shop's tape measurements and the corrections fitted from them (tape_routes.cpp).
void addTapeRoutes(Router& router, RouteContext& ctx);
/// /api/export/* and an item's pattern files (export_routes.cpp).
void addExportRoutes(Router& router, RouteContext& ctx);

/// Every route of a station (docs/api.md): the JSON API first (api_routes.cpp), so that a literal
/// route there wins over a pattern of a later resource, then review, settings, tape, exports.
void addStationRoutes(Router& router, Station& station);

}  // namespace garmcap::daemon
