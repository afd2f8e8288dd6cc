#pragma once
// From catalog items to shop items, and from an export request to its shop options: what the
// station's export routes (export_routes.cpp) and the hub's chain-wide exports (daemon/hub)
// share, so that both write the same files by the same rules (docs/exports.md). The file
// writers themselves are export_shop.h.

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "garmcap/daemon/catalog.h"
#include "garmcap/daemon/config.h"
#include "garmcap/daemon/export_shop.h"
#include "garmcap/daemon/http_router.h"
#include "garmcap/dsw/size_guide.h"

namespace garmcap::daemon {

/// The photos that go to shops, in the order shops show them: the front, then the back (from a
/// back shot). Each slot takes the first of its kinds the item has: the ghost-mannequin front,
/// which a back shot makes, before the plain front. All are the square JPEG on white; the cut-out
/// and the 4:5 crop are the same photos again (shops composite nothing), so they are not sent.
const std::vector<std::vector<std::string>>& shopImageSlots();

/// "jpg", "png" or "webp" for an image's media type; "" for any other.
std::string imageExtension(const std::string& mediaType);

/// Where an export links an item's image, relative to the public base URL (and its path in
/// catalog.zip): "images/<id>-<kind>.<ext>". The station serves the same names under
/// /api/export/files/, the hub under its own /api/export/files/ with its item ids.
std::string exportImagePath(std::int64_t id, const std::string& kind, const std::string& mediaType);

/// The stored size guide (dsw::sizeGuideJson); a malformed one throws naming the item.
std::optional<dsw::SizeGuide> storedSizeGuide(const Item& item,
                                              const std::optional<nlohmann::json>& guide);

/// Catalog item -> shop item: the piece, its size guide, its colours ("navy/white": Merchant
/// names, dominant first) and whether it is a print; an empty title becomes the default title.
ExportItem toExportItem(const Item& item, const std::optional<nlohmann::json>& guide);

/// The items a shop can take, `guides[i]` being the size guide of `items[i]`. One without a SKU
/// is left out with a warning saying what to do, never exported under a made-up SKU; `label`
/// names an item in that warning ("item 7").
std::vector<ExportItem> shopItems(const std::vector<Item>& items,
                                  const std::vector<std::optional<nlohmann::json>>& guides,
                                  std::vector<std::string>& warnings,
                                  const std::function<std::string(const Item&)>& label);

/// The shop options of an export request: the settings `shop`, each overridden by its query
/// (base_url, store_url, store_platform, brand or vendor, currency, size_system, gender,
/// made_to_order=1, legacy=1). Throws BadRequest naming the query.
ShopOptions shopOptions(const RouteMatch& m, const ShopConfig& shop);

/// A file as a download: attachment named `fileName`, not cached.
Response downloadResponse(const std::string& contentType, std::string body,
                          const std::string& fileName);

/// What a person should know before importing (drafts, items left out) as headers:
/// X-Export-Warnings (the count) and X-Export-Warning-Text (printable ASCII, bounded; the full
/// text is in catalog.zip's README).
void setExportWarnings(Response& r, const std::vector<std::string>& warnings);

}  // namespace garmcap::daemon
