#pragma once
// The chain's shop exports at the hub (docs/hub.md, "Shop exports"): the station's files
// (export_shop.h), by the station's rules (export_items.h: approved items only, no SKU no row,
// no price a draft), over the approved items of every station or of one.
//
//   GET /api/export/shopify.csv?station=&base_url=&store_url=&brand=&legacy=1 ...
//   GET /api/export/woocommerce.csv?station=...   GET /api/export/merchant.tsv?station=...
//   GET /api/export/catalog.zip?station=...  the station's catalog.zip (hub_catalog_zip.h)
//   GET /api/export/files/images/<hub item id>-<kind>.<jpg|png|webp>   the images they link to
//
// The admin token exports every station's items (`station=` one); a station token its own.
// The shop files are written as they are read (stream routes, chunked): pages of 500 items from
// one snapshot, so the hub's memory does not grow with the chain (hub_exports.cpp); so is
// catalog.zip. Two exports are written at once at most (a third: 503).

#include <nlohmann/json.hpp>
#include <optional>

#include "garmcap/daemon/catalog.h"
#include "garmcap/daemon/http_router.h"
#include "garmcap/hub/hub_caller.h"
#include "garmcap/hub/hub_config.h"
#include "garmcap/hub/hub_store.h"

namespace garmcap::hub {

/// A hub item as the station's catalog item the export writers take: the hub's title, price
/// and status (the hub's once it owns them), measurements and images, the rest (notes, tags,
/// attributes, base size) from the station's item JSON. `id` is the hub's id, so image names
/// are unique across stations.
daemon::Item catalogItemOf(const HubItem& item);

/// The size guide the station sent with the item (`size_guide` of its JSON), if any.
std::optional<nlohmann::json> sizeGuideOf(const HubItem& item);

/// Adds the routes above; `store`, `config` and `logins` outlive the router. With `logins`, a
/// browser's session cookie stands for the token that opened it (hub_web_routes.h), with its
/// rights: the export page of the review UI downloads through it.
void addHubExportRoutes(daemon::Router& router, HubStore& store, const HubConfig& config,
                        const HubLogins* logins = nullptr);

}  // namespace garmcap::hub
