#pragma once
// catalog.zip and the pattern files' shared pieces: what the station's export routes
// (export_routes.cpp) and the hub's chain-wide exports (daemon/hub) both build, from catalog
// items, their size guides and their stored patterns, with the drafts library's writers (DXF,
// SVG, PDF, GarmentCode, RUL, Valentina). Pure functions of their inputs; the caller reads the
// catalog (SQLite at a station, PostgreSQL at the hub) and the image bytes.

#include <array>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "garmcap/daemon/catalog.h"
#include "garmcap/daemon/export_shop.h"
#include "garmcap/daemon/export_zip.h"
#include "garmcap/daemon/http_router.h"
#include "garmcap/drafts/export_pdf.h"
#include "garmcap/drafts/measurements.h"
#include "garmcap/drafts/pattern_export.h"

namespace garmcap::daemon {

/// The `size` query of the pattern routes: "base" (the pattern as measured) when absent. Throws
/// BadRequest (400) unless it is a size name: 1..16 of A-Z a-z 0-9 _ -.
std::string patternSizeParam(const RouteMatch& m);

/// How a pattern file names a size: the chart size the garment was measured as for "base".
std::string sizeLabel(const Item& it, const std::string& size);

/// The style name pattern files carry (DXF-AAMA STYLE, .RUL, GarmentCode): the SKU, else
/// "GC-<id>". Station and hub name an item's files alike, so a pattern maker gets the same
/// names from either.
std::string patternStyle(const Item& it);

/// The stem of an item's per-size pattern file names: "<sku>_<size>", else "item-<id>_<size>".
std::string patternFileBase(const Item& it, const std::string& size);

/// The graded run of an item: every stored size but "base", in size-guide order when there is
/// one; the sample size is the one the garment was measured as. None with fewer than 2 sizes.
std::optional<drafts::GradedRun> gradedRun(const Item& it,
                                           const std::optional<nlohmann::json>& guide,
                                           const std::map<std::string, nlohmann::json>& patterns);

/// The body measurements for Valentina: the pattern's (the body it was drafted for), else the
/// item's measurements that are Valentina known names.
drafts::Measurements vitMeasurements(const Item& it, const std::optional<nlohmann::json>& base);

/// The `paper` query of pattern.pdf: A4 (the default), US Letter or A0; BadRequest otherwise.
drafts::Paper paperParam(const RouteMatch& m);
/// "A4", "Letter", "A0": the paper in a PDF's file name.
const char* paperFileTag(drafts::Paper p);

/// The catalog's approved items as catalog.zip takes them: `sizeGuides[i]` and `patterns[i]`
/// (size -> pattern JSON) belong to `items[i]`.
struct CatalogContent {
  std::vector<Item> items;
  std::vector<std::optional<nlohmann::json>> sizeGuides;
  std::vector<std::map<std::string, nlohmann::json>> patterns;
};

struct CatalogZip {
  std::string bytes;
  std::vector<std::string> notes;  // also in its README.txt
};

/// One item's files in catalog.zip, in order: its shop photos (images/<id>-<kind>.<ext>), then
/// patterns/<item id>/: per stored size DXF and SVG (and garmentcode.json for "base"), graded
/// DXF + RUL with two or more graded sizes, measurements.vit. A pattern that fails is added to
/// `notes` (labelled by `label`), not thrown; a missing image is an ExportError.
std::vector<ZipEntry> catalogItemFiles(
    const Item& item, const std::optional<nlohmann::json>& sizeGuide,
    const std::map<std::string, nlohmann::json>& patterns,
    const std::function<std::optional<std::string>(const std::string&)>& readImage,
    const std::function<std::string(const Item&)>& label, std::vector<std::string>& notes);

/// README.txt of catalog.zip before its notes (each note then follows as "Note: <note>\n").
std::string catalogReadmeHead(const std::string& heading, std::size_t items,
                              const ShopOptions& options);

/// The shop files of catalog.zip, in their order in the archive, after the items' files.
struct CatalogShopFile {
  const char* name;
  ShopFile (*build)(const std::vector<ExportItem>&, const ShopOptions&);
};
const std::array<CatalogShopFile, 3>& catalogShopFiles();

/// catalog.zip: the shop photos (images/), each item's pattern files (patterns/<item id>/: DXF,
/// SVG, GarmentCode JSON, graded DXF + RUL, Valentina .vit), the three shop files and a README
/// headed by `heading` ("GarmCap Station catalog export"). `readImage` gives an image's bytes
/// by sha256 (none: ExportError). An item whose pattern files fail is noted, not fatal; a shop
/// file the options cannot make is left out with the reason. Throws ExportError.
CatalogZip catalogZip(
    const CatalogContent& content, const ShopOptions& options,
    const std::function<std::optional<std::string>(const std::string&)>& readImage,
    const std::function<std::string(const Item&)>& label, const std::string& heading);

}  // namespace garmcap::daemon
