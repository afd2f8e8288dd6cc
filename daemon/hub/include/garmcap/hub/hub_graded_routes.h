#pragma once
// The graded pattern files of any station's item at the hub, as the station serves them
// (daemon/src/export_routes.cpp), written from the patterns the station pushed (item_patterns:
// one per stored size, "base" = as measured) and the size guide in its item JSON, by the same
// drafts writers and the same graded run (export_catalog.h, gradedRun):
//
//   GET /api/items/<hub id>/pattern_graded.dxf   every graded size in one DXF-AAMA file
//   GET /api/items/<hub id>/pattern_graded.rul   its grade rule table
//   GET /api/items/<hub id>/nested_grading.svg   nested_grading.pdf   nested_grading.dxf
//   GET /api/items/<hub id>/garmentcode.json?size=
//   GET /api/items/<hub id>/measurements.vit     the body the draft was made for (Valentina)
//
// Who may read them: as the other item routes (hub_caller.h, readableItem). Markers are not
// served at the hub (nesting holds a core for seconds; the station lays them one at a time).

#include "garmcap/daemon/http_router.h"
#include "garmcap/hub/hub_caller.h"
#include "garmcap/hub/hub_config.h"
#include "garmcap/hub/hub_store.h"

namespace garmcap::hub {

/// Adds the routes above; everything outlives the router.
void addHubGradedRoutes(daemon::Router& router, HubStore& store, const HubConfig& config,
                        const HubLogins* logins);

}  // namespace garmcap::hub
