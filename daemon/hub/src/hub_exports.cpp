#include "garmcap/hub/hub_exports.h"

#include <functional>
#include <map>

#include "garmcap/daemon/export_items.h"
#include "garmcap/daemon/export_shop.h"
#include "garmcap/daemon/utf8.h"
#include "garmcap/hub/hub_caller.h"

namespace garmcap::hub {

namespace http = daemon::http;
using daemon::BadRequest;
using daemon::jsonError;
using daemon::Reply;
using daemon::Request;
using daemon::Response;
using daemon::RouteMatch;

namespace {

std::string docString(const nlohmann::json& doc, const char* key) {
  return doc.contains(key) && doc[key].is_string() ? doc[key].get<std::string>() : "";
}

using ShopBuild = std::function<daemon::ShopFile(const std::vector<daemon::ExportItem>&,
                                                 const daemon::ShopOptions&)>;

const char* kReadsWhat =
    "a station token exports only its own station's items; the admin token every station's";

}  // namespace

daemon::Item catalogItemOf(const HubItem& h) {
  daemon::Item it;
  it.id = h.id;
  it.sku = h.sku;
  it.title = h.title;
  it.priceCents = h.priceCents;
  it.status = h.status;
  it.type = h.type;
  it.notes = docString(h.doc, "notes");
  it.baseSize = docString(h.doc, "base_size");
  if (h.doc.contains("tags") && h.doc["tags"].is_array())
    for (const auto& t : h.doc["tags"])
      if (t.is_string())
        it.tags.push_back(t.get<std::string>());
  if (h.doc.contains("attributes") && h.doc["attributes"].is_object())
    for (const auto& [k, v] : h.doc["attributes"].items())
      if (v.is_string())
        it.attributes[k] = v.get<std::string>();
  it.measurementsCm = h.measurementsCm;
  for (const auto& im : h.images)
    it.images.push_back({im.kind, im.sha256, im.mediaType, 0});
  it.createdAt = h.createdAt;
  it.updatedAt = h.updatedAt;
  it.deletedAt = h.deletedAt;
  return it;
}

std::optional<nlohmann::json> sizeGuideOf(const HubItem& h) {
  if (!h.doc.contains("size_guide") || h.doc["size_guide"].is_null())
    return std::nullopt;
  return h.doc["size_guide"];
}

void addHubExportRoutes(daemon::Router& router, HubStore& store, const HubConfig& config) {
  auto shopRoute = [&store, &config](std::string name, std::string type, ShopBuild build) {
    return
        [&store, &config, name, type, build](const Request& req, const RouteMatch& m, Reply reply) {
          const Caller c = callerOf(req, store, config);
          if (!c.any())
            return reply(unauthorized("a station or admin token is required"));
          const auto scope = readScope(c, m);
          if (!scope)
            return reply(jsonError(http::status::forbidden, kReadsWhat));
          const daemon::ShopOptions options = daemon::shopOptions(m, config.shop);
          std::vector<daemon::Item> items;
          std::vector<std::optional<nlohmann::json>> guides;
          std::map<std::int64_t, std::string> labels;  // hub id -> "item 12 (shop1 #7)"
          for (const auto& h : store.approvedItems(*scope)) {
            items.push_back(catalogItemOf(h));
            guides.push_back(sizeGuideOf(h));
            labels[h.id] = "item " + std::to_string(h.id) + " (" + h.station + " #" +
                           std::to_string(h.localId) + ")";
          }
          try {
            std::vector<std::string> warnings;
            const auto shop = daemon::shopItems(
                items, guides, warnings, [&](const daemon::Item& it) { return labels.at(it.id); });
            daemon::ShopFile f = build(shop, options);
            warnings.insert(warnings.end(), f.warnings.begin(), f.warnings.end());
            Response r = daemon::downloadResponse(type, std::move(f.bytes), name);
            daemon::setExportWarnings(r, warnings);
            reply(std::move(r));
          } catch (const daemon::ExportError& e) {
            reply(jsonError(http::status::unprocessable_entity, e.what()));
          }
        };
  };
  router.add(http::verb::get, "/api/export/shopify.csv",
             shopRoute("shopify.csv", "text/csv; charset=utf-8", daemon::shopifyCsv));
  router.add(http::verb::get, "/api/export/woocommerce.csv",
             shopRoute("woocommerce.csv", "text/csv; charset=utf-8", daemon::wooCommerceCsv));
  router.add(
      http::verb::get, "/api/export/merchant.tsv",
      shopRoute("merchant.tsv", "text/tab-separated-values; charset=utf-8", daemon::merchantTsv));

  // The images the exports link to (daemon::exportImagePath, hub ids): "<id>-<kind>" names,
  // resolved through the hub's items, of approved items the caller may read.
  auto imageFile = [&store, &config](std::string ext) {
    return [&store, &config, ext](const Request& req, const RouteMatch& m, Reply reply) {
      const Caller c = callerOf(req, store, config);
      if (!c.any())
        return reply(unauthorized("a station or admin token is required"));
      const std::string name = m.param("name");
      const auto dash = name.find('-');
      if (dash == std::string::npos || dash == 0)
        throw BadRequest("image name must be <item id>-<kind>, got '" + daemon::quoteInput(name) +
                         "'");
      RouteMatch idOnly;
      idOnly.params["id"] = name.substr(0, dash);
      const std::int64_t id = idOnly.id("id");
      const std::string kind = name.substr(dash + 1);
      const auto it = store.item(id);
      if (!it || it->deletedAt || it->status != "approved" ||
          (!c.admin && it->station != *c.station))
        return reply(jsonError(http::status::not_found, "no approved item " + std::to_string(id)));
      for (const auto& im : it->images)
        if (im.kind == kind && daemon::imageExtension(im.mediaType) == ext) {
          auto bytes = store.blob(im.sha256);
          if (!bytes)
            return reply(jsonError(http::status::internal_server_error,
                                   "image " + im.sha256 + " is missing from the hub"));
          Response r = daemon::textResponse(http::status::ok, im.mediaType, std::move(*bytes));
          r.set(http::field::cache_control, "public, max-age=86400");
          return reply(std::move(r));
        }
      reply(jsonError(http::status::not_found,
                      "item " + std::to_string(id) + " has no " + ext + " image '" + kind + "'"));
    };
  };
  router.add(http::verb::get, "/api/export/files/images/{name}.jpg", imageFile("jpg"));
  router.add(http::verb::get, "/api/export/files/images/{name}.png", imageFile("png"));
  router.add(http::verb::get, "/api/export/files/images/{name}.webp", imageFile("webp"));
}

}  // namespace garmcap::hub
