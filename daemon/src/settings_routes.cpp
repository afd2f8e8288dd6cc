// The shop's setup screen (issue 17): what the shop exports need to know about the shop, asked
// once in the web UI instead of in the config file.
//
//   GET /api/settings/shop  -> 200 {"settings": {...in force...}, "saved": {...}, "missing": [...]}
//   PUT /api/settings/shop  {"brand": "Atelier Nord", "store_url": "https://...", ...}
//     -> 200 as GET; 400 naming the key for an unknown key or a bad value (nothing stored)
//
// Keys and checks are the config's [shop] section's (docs/exports.md); saved values win over
// the config file and survive restarts (the catalog's settings table). `missing` lists what the
// exports still lack to publish: the brand, the store URL, the public image URL.

#include "garmcap/daemon/catalog.h"
#include "garmcap/daemon/config.h"
#include "garmcap/daemon/http_router.h"
#include "garmcap/daemon/station_routes.h"

namespace garmcap::daemon {
namespace {

nlohmann::json settingsView(const ShopConfig& shop, const nlohmann::json& saved) {
  nlohmann::json missing = nlohmann::json::array();
  if (shop.brand.empty())
    missing.push_back("brand");
  if (shop.storeUrl.empty())
    missing.push_back("store_url");
  if (shop.publicBaseUrl.empty())
    missing.push_back("public_base_url");
  return {{"settings", shopSettingsJson(shop)}, {"saved", saved}, {"missing", missing}};
}

}  // namespace

void addSettingsRoutes(Router& router, RouteContext& ctx) {
  RouteContext* c = &ctx;
  router.add(
      http::verb::get, "/api/settings/shop", [c](const Request&, const RouteMatch&, Reply reply) {
        reply(
            jsonResponse(http::status::ok, settingsView(c->shopConfig(), c->savedShopSettings())));
      });
  router.add(
      http::verb::put, "/api/settings/shop",
      [c](const Request& req, const RouteMatch&, Reply reply) {
        const nlohmann::json changes = parseJsonBody(req);
        c->withCatalog(
            [c, reply, changes](Catalog& cat) {
              const ShopConfig shop = c->saveShopSettings(cat, changes);
              reply(jsonResponse(http::status::ok, settingsView(shop, c->savedShopSettings())));
            },
            reply);
      });
}

}  // namespace garmcap::daemon
