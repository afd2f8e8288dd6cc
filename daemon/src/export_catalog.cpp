#include "garmcap/daemon/export_catalog.h"

#include <algorithm>
#include <array>
#include <iterator>

#include "garmcap/daemon/export_items.h"
#include "garmcap/daemon/export_zip.h"
#include "garmcap/daemon/http_guard.h"
#include "garmcap/daemon/utf8.h"
#include "garmcap/drafts/export_dxf_aama.h"
#include "garmcap/drafts/export_garmentcode.h"
#include "garmcap/drafts/export_rul.h"
#include "garmcap/drafts/export_svg.h"
#include "garmcap/drafts/pattern_io.h"

namespace garmcap::daemon {

namespace {

// The images catalog.zip holds: the shop photos (shopImageSlots: the front, the ghost-mannequin
// front and the back a back shot adds), each also as WebP for shops that take it (the CSVs keep
// linking the JPEG, which every shop imports).
bool zipImageKind(const std::string& kind) {
  for (const auto& slot : shopImageSlots())
    for (const auto& k : slot)
      if (kind == k || kind == k + "_webp")
        return true;
  return false;
}

}  // namespace

std::string patternSizeParam(const RouteMatch& m) {
  auto size = m.queryValue("size").value_or("base");
  if (size.empty() || size.size() > 16 || !std::all_of(size.begin(), size.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
      }))
    throw BadRequest("query 'size' must be a size name like 55 or M, got '" + quoteInput(size) +
                     "'");
  return size;
}

namespace {

// An item's file names start with its SKU, else "item-<id>" (the SKU is checked to be a safe
// file name where it is set).
std::string itemFileStem(const Item& it) {
  return it.sku.empty() ? "item-" + std::to_string(it.id) : it.sku;
}

}  // namespace

std::string sizeLabel(const Item& it, const std::string& size) {
  return size == "base" && !it.baseSize.empty() ? it.baseSize : size;
}

std::string patternStyle(const Item& it) {
  return it.sku.empty() ? "GC-" + std::to_string(it.id) : it.sku;
}

std::string patternFileBase(const Item& it, const std::string& size) {
  return itemFileStem(it) + "_" + size;
}

std::optional<drafts::GradedRun> gradedRun(const Item& it,
                                           const std::optional<nlohmann::json>& guide,
                                           const std::map<std::string, nlohmann::json>& patterns) {
  std::vector<std::string> sizes;
  if (const auto g = storedSizeGuide(it, guide))
    for (const auto& row : g->rows)
      sizes.push_back(row.size);
  if (sizes.empty())
    for (const auto& s : it.sizes)
      if (s != "base")
        sizes.push_back(s);
  drafts::GradedRun run;
  run.style = patternStyle(it);
  for (const auto& s : sizes) {
    auto p = patterns.find(s);
    if (p == patterns.end())
      continue;
    run.sizes.push_back(s);
    run.patterns.push_back(
        drafts::patternFromJsonValue(p->second, "item " + std::to_string(it.id) + " size " + s));
  }
  if (run.sizes.size() < 2)
    return std::nullopt;
  run.sampleSize = std::find(run.sizes.begin(), run.sizes.end(), it.baseSize) != run.sizes.end()
                       ? it.baseSize
                       : run.sizes[run.sizes.size() / 2];
  return run;
}

drafts::Measurements vitMeasurements(const Item& it, const std::optional<nlohmann::json>& base) {
  if (base) {
    auto p = drafts::patternFromJsonValue(*base, "item " + std::to_string(it.id) + " pattern");
    if (!p.measurements.empty())
      return p.measurements;
  }
  drafts::Measurements m;
  for (const auto& [n, v] : it.measurementsCm)
    if (drafts::isKnownMeasurement(n))
      m.set(n, v);
  return m;
}

drafts::Paper paperParam(const RouteMatch& m) {
  const auto v = m.queryValue("paper");
  if (!v || v->empty())
    return drafts::Paper::kA4;
  try {
    return drafts::parsePaper(*v);
  } catch (const std::invalid_argument&) {
    throw BadRequest("query 'paper' must be a4, letter or a0, got '" + quoteInput(*v) + "'");
  }
}

const char* paperFileTag(drafts::Paper p) {
  switch (p) {
    case drafts::Paper::kA4:
      return "A4";
    case drafts::Paper::kLetter:
      return "Letter";
    case drafts::Paper::kA0:
      return "A0";
  }
  return "paper";
}

std::vector<ZipEntry> catalogItemFiles(
    const Item& it, const std::optional<nlohmann::json>& guide,
    const std::map<std::string, nlohmann::json>& pats,
    const std::function<std::optional<std::string>(const std::string&)>& readImage,
    const std::function<std::string(const Item&)>& label, std::vector<std::string>& notes) {
  std::vector<ZipEntry> files;
  const std::string style = itemFileStem(it);
  for (const auto& im : it.images) {
    const std::string ext = imageExtension(im.mediaType);
    if (ext.empty() || !zipImageKind(im.kind))
      continue;
    auto bytes = readImage(im.sha256);
    if (!bytes)
      throw ExportError("image " + im.sha256 + " is missing from the store");
    files.push_back({exportImagePath(it.id, im.kind, im.mediaType), std::move(*bytes)});
  }
  const std::string dir = "patterns/" + std::to_string(it.id) + "/";
  for (const auto& [size, json] : pats) {
    try {
      auto p = drafts::patternFromJsonValue(json, "item " + std::to_string(it.id));
      const drafts::PieceText t{style, sizeLabel(it, size)};
      files.push_back({dir + size + ".dxf", drafts::patternDxf(p, t)});
      files.push_back({dir + size + ".svg", drafts::patternSvg(p, t)});
      if (size == "base")
        files.push_back({dir + "garmentcode.json", drafts::garmentCodeJson(p, t)});
    } catch (const std::exception& e) {
      notes.push_back(label(it) + " size " + size + ": " + e.what());
    }
  }
  try {
    if (auto run = gradedRun(it, guide, pats)) {
      files.push_back({dir + "graded.dxf", drafts::gradedDxf(*run)});
      files.push_back({dir + "graded.rul", drafts::gradeRuleTable(*run)});
    }
    auto base = pats.find("base");
    auto vm = vitMeasurements(it, base == pats.end() ? std::nullopt : std::optional(base->second));
    if (!vm.empty())
      files.push_back({dir + "measurements.vit", drafts::measurementsToVit(vm)});
  } catch (const std::exception& e) {
    notes.push_back(label(it) + ": " + e.what());
  }
  return files;
}

std::string catalogReadmeHead(const std::string& heading, std::size_t items, const ShopOptions& o) {
  return heading + ": " + std::to_string(items) + " approved items.\n" +
         (o.publicBaseUrl.empty()
              ? std::string("No public address is set ([shop] public_base_url), "
                            "so the shop files cannot link the images yet.\n")
              : "Upload the folder so that images/ is reachable at " + o.publicBaseUrl +
                    "/images/ before importing the CSVs.\n") +
         "Patterns: patterns/<item id>/ (DXF in mm, SVG 1:1, GarmentCode JSON, "
         "Valentina .vit, graded DXF + RUL when graded).\n";
}

const std::array<CatalogShopFile, 3>& catalogShopFiles() {
  static const std::array<CatalogShopFile, 3> kFiles{
      CatalogShopFile{"shopify.csv", &shopifyCsv},
      CatalogShopFile{"woocommerce.csv", &wooCommerceCsv},
      CatalogShopFile{"merchant.tsv", &merchantTsv}};
  return kFiles;
}

CatalogZip catalogZip(
    const CatalogContent& content, const ShopOptions& o,
    const std::function<std::optional<std::string>(const std::string&)>& readImage,
    const std::function<std::string(const Item&)>& label, const std::string& heading) {
  CatalogZip out;
  std::vector<std::string>& notes = out.notes;
  const std::vector<ExportItem> items = shopItems(content.items, content.sizeGuides, notes, label);
  std::vector<ZipEntry> files;
  for (size_t i = 0; i < content.items.size(); ++i) {
    auto itemFiles = catalogItemFiles(content.items[i], content.sizeGuides[i], content.patterns[i],
                                      readImage, label, notes);
    std::move(itemFiles.begin(), itemFiles.end(), std::back_inserter(files));
  }
  for (const auto& [file, build] : catalogShopFiles()) {
    // A shop file the settings cannot make yet (no public address) is left out with the
    // reason; the patterns and photos are still worth having.
    try {
      ShopFile f = build(items, o);
      for (const auto& w : f.warnings)
        notes.push_back(std::string(file) + ": " + w);
      files.push_back({file, std::move(f.bytes)});
    } catch (const ExportError& e) {
      notes.push_back(std::string(file) + " left out: " + e.what());
    }
  }
  std::string readme = catalogReadmeHead(heading, items.size(), o);
  for (const auto& n : notes)
    readme += "Note: " + n + "\n";
  files.push_back({"README.txt", readme});
  out.bytes = storeZip(files);
  return out;
}

}  // namespace garmcap::daemon
