#pragma once
// The patterns of any station's item at the hub (docs/hub.md, "Patterns and catalog.zip"),
// written from the patterns each station pushes with its items by the drafts library's writers
// (the chain's catalog.zip is an export route: hub_exports.h, hub_catalog_zip.h):
//
//   GET /api/items/<hub id>/patterns            {"id", "sizes": [...]}
//   GET /api/items/<hub id>/pattern.json?size=  the stored pattern (size "base" by default)
//   GET /api/items/<hub id>/pattern.svg?size=   1:1 SVG, pattern.dxf (DXF-AAMA, mm),
//   GET /api/items/<hub id>/pattern.pdf?size=&paper=a4|letter|a0
//
// The admin token reads every station's; a station token its own station's (another's item is
// a 404).

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "garmcap/daemon/http_router.h"
#include "garmcap/hub/hub_caller.h"
#include "garmcap/hub/hub_config.h"
#include "garmcap/hub/hub_store.h"

namespace garmcap::hub {

/// The `patterns` of a push body: an object of size -> pattern JSON object, or absent (the
/// station's patterns stay as they are). Throws BadRequest for anything else.
std::optional<std::map<std::string, nlohmann::json>> pushedPatterns(const nlohmann::json& body);

/// Adds the routes above; `store`, `config` and `logins` outlive the router. With `logins`, a
/// browser's session cookie stands for its token, as on the other read routes.
void addHubPatternRoutes(daemon::Router& router, HubStore& store, const HubConfig& config,
                         const HubLogins* logins = nullptr);

}  // namespace garmcap::hub
