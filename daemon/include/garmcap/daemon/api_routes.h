#pragma once
// The station's JSON API (docs/api.md): status, events, captures, jobs, items and their images
// and patterns. station_routes.h registers it first, then the other resources.

#include <nlohmann/json.hpp>
#include <string>

#include "garmcap/daemon/export_catalog.h"
#include "garmcap/daemon/http_router.h"
#include "garmcap/daemon/station.h"

namespace garmcap::daemon {

void addApiRoutes(Router& router, Station& station);

/// A stored size guide (dsw::sizeGuideJson) as dsw::sizeGuideCsv. Throws drafts::ParseError
/// naming the field on a malformed guide.
std::string sizeGuideCsv(const nlohmann::json& guide);

struct Item;

/// 404 for a size `item` has no pattern of, naming the size and the sizes the item has, so that
/// a client sees at once what it may ask for.
Response noPatternForSize(const Item& item, const std::string& size);

/// 422 for an item whose garment could not be drafted: it has no pattern at all (captures since
/// storeBasePattern) or a stored pattern without pieces (catalogs written before), so that a
/// client never gets an empty pattern with 200. The error is "no pattern: <reason>", the reason
/// taken from the item's "no pattern: ..." warnings (all its warnings if none says it).
Response noDraftedPattern(const Item& item, const std::string& size);

}  // namespace garmcap::daemon
