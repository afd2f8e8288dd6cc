// HTTP routes of the exports (issue 8): shop files of the approved catalog, pattern files of one
// item, and the image files the shop CSVs link to. Catalog reads run on the station strand, file
// building on the worker pool; the pure builders live in export_shop/export_zip/export_catalog
// (shared with the hub) and, for
// pattern files, in drafts/ (export_dxf_aama, export_rul, export_garmentcode, export_pdf).
//
//   GET /api/export/shopify.csv?base_url=&legacy=1   GET /api/export/woocommerce.csv?base_url=
//   GET /api/export/merchant.tsv?base_url=&store_url=   GET /api/export/catalog.zip?base_url=
//   GET /api/export/files/images/{id}-{kind}.{jpg,png}  (the default public base URL's images)
//   GET /api/items/{id}/pattern.dxf?size=   pattern.pdf?size=&paper=a4|letter|a0
//   GET /api/items/{id}/garmentcode.json?size=
//   GET /api/items/{id}/pattern_graded.dxf   pattern_graded.rul   measurements.vit
//   GET /api/items/{id}/nested_grading.svg   nested_grading.pdf   nested_grading.dxf
//   GET /api/items/{id}/marker.svg|pdf|dxf|json?width=<cm>&sizes=<size,size,...>
//
// Only approved items are exported to shops (a capture waiting for review is not). Options come
// from the query (the web UI keeps them per browser); without base_url the images are linked
// through this station's own /api/export/files/ (reachable on the shop's LAN only).

#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <memory>
#include <sstream>

#include "garmcap/daemon/api_routes.h"
#include "garmcap/daemon/catalog.h"
#include "garmcap/daemon/content_store.h"
#include "garmcap/daemon/export_catalog.h"
#include "garmcap/daemon/export_items.h"
#include "garmcap/daemon/export_shop.h"
#include "garmcap/daemon/export_zip.h"
#include "garmcap/daemon/http_guard.h"
#include "garmcap/daemon/http_router.h"
#include "garmcap/daemon/station_routes.h"
#include "garmcap/drafts/export_dxf_aama.h"
#include "garmcap/drafts/export_garmentcode.h"
#include "garmcap/drafts/export_nested_grading.h"
#include "garmcap/drafts/export_pdf.h"
#include "garmcap/drafts/export_rul.h"
#include "garmcap/drafts/export_svg.h"
#include "garmcap/drafts/marker.h"
#include "garmcap/drafts/measurements.h"
#include "garmcap/drafts/pattern_io.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/dsw/size_guide.h"

namespace garmcap::daemon {
namespace {

using drafts::GradedRun;
using drafts::PieceText;

constexpr int kMaxExportItems = 2000;
// What the export needs from the catalog, copied on the strand.
using CatalogSnapshot = CatalogContent;

CatalogSnapshot snapshot(Catalog& c, bool withPatterns) {
  CatalogSnapshot s;
  ItemQuery q;
  q.status = kStatusApproved;
  q.limit = 500;
  while (static_cast<int>(s.items.size()) < kMaxExportItems) {
    auto [page, total] = c.items(q);
    for (auto& it : page)
      s.items.push_back(std::move(it));
    q.offset += static_cast<int>(page.size());
    if (page.empty() || q.offset >= total)
      break;
  }
  for (const auto& it : s.items) {
    s.sizeGuides.push_back(c.sizeGuide(it.id));
    std::map<std::string, nlohmann::json> pats;
    if (withPatterns)
      for (const auto& size : it.sizes)
        if (auto p = c.pattern(it.id, size))
          pats[size] = *p;
    s.patterns.push_back(std::move(pats));
  }
  return s;
}

// How an export's warnings name a station's item.
std::string itemLabel(const Item& it) {
  return "item " + std::to_string(it.id);
}

// Fabric widths a marker is laid on: from a narrow lining to the widest wide goods; outside
// that the number is a typing error (150 typed as 15 or 1500), not a fabric.
constexpr double kMinFabricWidthCm = 50.0;
constexpr double kMaxFabricWidthCm = 400.0;

// The queries of the marker routes: `width` in cm (default 150) and `sizes`, a comma list of
// the item's sizes (default: none given, the item's own size). Only their form is checked here;
// whether the item has the sizes is checked against its patterns. How many pieces it may lay
// is the station's ([marker] max_pieces), checked by drafts::layMarker before nesting.
struct MarkerQuery {
  double widthCm = 150.0;
  std::vector<std::string> sizes;
  int maxPieces = 0;
};

MarkerQuery markerQuery(const RouteMatch& m) {
  MarkerQuery q;
  if (const auto w = m.queryValue("width"); w && !w->empty()) {
    double v = 0;
    const auto [end, ec] = std::from_chars(w->data(), w->data() + w->size(), v);
    if (ec != std::errc() || end != w->data() + w->size() || !std::isfinite(v) ||
        v < kMinFabricWidthCm || v > kMaxFabricWidthCm)
      throw BadRequest(
          "query 'width' must be the fabric width in cm, a number from 50 to 400, got '" +
          quoteInput(*w) + "'");
    q.widthCm = v;
  }
  if (const auto list = m.queryValue("sizes"); list && !list->empty()) {
    const std::string& rest = *list;
    for (std::size_t at = 0;;) {
      const std::size_t comma = rest.find(',', at);
      const std::string s =
          rest.substr(at, comma == std::string::npos ? std::string::npos : comma - at);
      if (s.empty() || s.size() > 16 || !std::all_of(s.begin(), s.end(), [](char c) {
            return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
          }))
        throw BadRequest("query 'sizes' must be a comma list of size names like 55,66, got '" +
                         quoteInput(*list) + "'");
      if (std::find(q.sizes.begin(), q.sizes.end(), s) != q.sizes.end())
        throw BadRequest("query 'sizes' names size '" + s + "' twice");
      q.sizes.push_back(s);
      if (comma == std::string::npos)
        break;
      at = comma + 1;
    }
  }
  return q;
}

// Markers laid at once per station. Nesting keeps a core busy for seconds (a dress in five
// sizes: about 4 s on the station's 2 cores) and runs on the 2 threads that serve every export;
// 20 marker requests at once would hold both cores for a minute while captures wait for CPU.
// One runs, the others are answered 503 with Retry-After at once (nothing queues behind it).
constexpr int kMaxMarkersAtOnce = 1;
constexpr int kMarkerRetryAfterS = 5;

// The marker slots of one station: a token holds one until it is released or destroyed.
class MarkerSlots : public std::enable_shared_from_this<MarkerSlots> {
 public:
  class Token {
   public:
    explicit Token(std::shared_ptr<MarkerSlots> slots) : slots_(std::move(slots)) {}
    Token(const Token&) = delete;
    Token& operator=(const Token&) = delete;
    ~Token() { release(); }
    void release() {
      if (!released_.exchange(true))
        slots_->busy_.fetch_sub(1);
    }

   private:
    std::shared_ptr<MarkerSlots> slots_;
    std::atomic<bool> released_{false};
  };

  /// A token when fewer than kMaxMarkersAtOnce markers are being laid, else nullptr.
  std::shared_ptr<Token> tryAcquire() {
    int n = busy_.load();
    while (n < kMaxMarkersAtOnce)
      if (busy_.compare_exchange_weak(n, n + 1))
        return std::make_shared<Token>(shared_from_this());
    return nullptr;
  }

 private:
  std::atomic<int> busy_{0};
};

Response markerBusy() {
  Response r = jsonError(http::status::service_unavailable,
                         "a marker is being laid on this station already (one at a time, so "
                         "that captures keep their CPU); retry in " +
                             std::to_string(kMarkerRetryAfterS) + " s");
  r.set(http::field::retry_after, std::to_string(kMarkerRetryAfterS));
  return r;
}

// A width as it goes into a file name: 150, 137.5.
std::string widthTag(double cm) {
  std::ostringstream os;
  os << cm;
  return os.str();
}

// Pattern files of one item. `build` gets the item, its size guide, its patterns and the size
// asked for.
using PatternBuild =
    std::function<Response(const Item&, const std::optional<nlohmann::json>&,
                           const std::map<std::string, nlohmann::json>&, const std::string&)>;
using GradedWrite = std::function<Response(const Item&, const GradedRun&)>;
using ShopBuild = std::function<ShopFile(const std::vector<ExportItem>&, const ShopOptions&)>;
enum class MarkerFile { kSvg, kPdf, kDxf, kJson };

// A named route handler bound to the station's route context (Router takes plain callables).
template <class Handler>
auto withContext(RouteContext* c, Handler handler) {
  return [c, handler](auto&&... args) { handler(c, std::forward<decltype(args)>(args)...); };
}

// A shop file (`name`, served as `type`): the approved items snapshot on the strand, the file
// built on the pool.
Handler shopFileRoute(RouteContext* c, std::string name, std::string type, ShopBuild build) {
  return [c, name, type, build](const Request&, const RouteMatch& m, Reply reply) {
    const ShopOptions o = shopOptions(m, c->shopConfig());
    c->withCatalog(
        [c, reply, o, name, type, build](Catalog& cat) {
          auto snap = std::make_shared<CatalogSnapshot>(snapshot(cat, false));
          c->offload(
              [reply, o, name, type, build, snap] {
                try {
                  std::vector<std::string> warnings;
                  const auto items = shopItems(snap->items, snap->sizeGuides, warnings, itemLabel);
                  ShopFile f = build(items, o);
                  warnings.insert(warnings.end(), f.warnings.begin(), f.warnings.end());
                  Response r = downloadResponse(type, std::move(f.bytes), name);
                  setExportWarnings(r, warnings);
                  reply(std::move(r));
                } catch (const ExportError& e) {
                  reply(jsonError(http::status::unprocessable_entity, e.what()));
                } catch (const std::exception& e) {
                  reply(jsonError(http::status::internal_server_error, e.what()));
                }
              },
              reply);
        },
        reply);
  };
}

// GET /api/export/catalog.zip: photos, patterns and the shop files of every approved item.
void getCatalogZip(RouteContext* c, const Request&, const RouteMatch& m, Reply reply) {
  const ShopOptions o = shopOptions(m, c->shopConfig());
  c->withCatalog(
      [c, reply, o](Catalog& cat) {
        auto snap = std::make_shared<CatalogSnapshot>(snapshot(cat, true));
        c->offload(
            [c, reply, o, snap] {
              try {
                CatalogZip zip = catalogZip(
                    *snap, o, [c](const std::string& sha) { return c->store().read(sha); },
                    itemLabel, "GarmCap Station catalog export");
                Response r =
                    downloadResponse("application/zip", std::move(zip.bytes), "catalog.zip");
                setExportWarnings(r, zip.notes);
                reply(std::move(r));
              } catch (const ExportError& e) {
                reply(jsonError(http::status::unprocessable_entity, e.what()));
              } catch (const std::exception& e) {
                reply(jsonError(http::status::internal_server_error, e.what()));
              }
            },
            reply);
      },
      reply);
}

// The images the default base URL links to: "<id>-<kind>" names only, resolved through the
// catalog (never through the file system).
Handler exportImageRoute(RouteContext* c, std::string ext) {
  return [c, ext](const Request&, const RouteMatch& m, Reply reply) {
    const std::string name = m.param("name");
    const auto dash = name.find('-');
    if (dash == std::string::npos || dash == 0)
      throw BadRequest("image name must be <item id>-<kind>, got '" + quoteInput(name) + "'");
    RouteMatch idOnly;
    idOnly.params["id"] = name.substr(0, dash);
    const std::int64_t id = idOnly.id("id");
    const std::string kind = name.substr(dash + 1);
    c->withCatalog(
        [c, reply, id, kind, ext](Catalog& cat) {
          auto it = cat.item(id);
          if (!it || it->status != kStatusApproved)
            return reply(
                jsonError(http::status::not_found, "no approved item " + std::to_string(id)));
          for (const auto& im : it->images)
            if (im.kind == kind && imageExtension(im.mediaType) == ext) {
              const ImageRef ref = im;
              return c->offload(
                  [c, reply, ref] {
                    auto bytes = c->store().read(ref.sha256);
                    if (!bytes)
                      return reply(jsonError(http::status::internal_server_error,
                                             "image " + ref.sha256 + " is missing from the store"));
                    Response r = textResponse(http::status::ok, ref.mediaType, std::move(*bytes));
                    r.set(http::field::cache_control, "public, max-age=86400");
                    reply(std::move(r));
                  },
                  reply);
            }
          reply(jsonError(http::status::not_found, "item " + std::to_string(id) + " has no " + ext +
                                                       " image '" + kind + "'"));
        },
        reply);
  };
}

// GET /api/size_charts/{name}.vst: a built-in size chart as a Valentina multisize table (every
// size, labelled): pure data, no catalog access, so it is answered on the spot.
void getSizeChartVst(const Request&, const RouteMatch& m, Reply reply) {
  const std::string name = m.param("name");
  for (const auto& chart : drafts::sizeCharts()) {
    if (chart.name == name)
      return reply(
          downloadResponse("application/xml", drafts::chartToVst(chart), chart.name + ".vst"));
  }
  std::string known;
  for (const auto& chart : drafts::sizeCharts())
    known += (known.empty() ? "" : ", ") + chart.name;
  reply(jsonError(http::status::not_found,
                  "no size chart '" + quoteInput(name) + "' (known: " + known + ")"));
}

// The handler of a pattern file of one item: the item, its size guide and patterns read on the
// strand, the file built by `build` on the pool.
Handler patternRoute(RouteContext* c, PatternBuild build) {
  return [c, build](const Request&, const RouteMatch& m, Reply reply) {
    const auto id = m.id("id");
    const std::string size = patternSizeParam(m);
    c->withCatalog(
        [c, reply, id, size, build](Catalog& cat) {
          auto it = cat.item(id);
          if (!it)
            return reply(jsonError(http::status::not_found, "no item " + std::to_string(id)));
          auto guide = cat.sizeGuide(id);
          std::map<std::string, nlohmann::json> pats;
          for (const auto& s : it->sizes)
            if (auto p = cat.pattern(id, s))
              pats[s] = *p;
          if (auto p = pats.find(size); p != pats.end() && patternIsEmpty(p->second))
            return reply(noDraftedPattern(*it, size));
          c->offload(
              [reply, item = *it, guide, pats, size, build] {
                try {
                  reply(build(item, guide, pats, size));
                } catch (const ExportError& e) {
                  reply(jsonError(http::status::unprocessable_entity, e.what()));
                } catch (const drafts::PatternExportError& e) {
                  reply(jsonError(http::status::unprocessable_entity, e.what()));
                } catch (const std::exception& e) {
                  reply(jsonError(http::status::internal_server_error, e.what()));
                }
              },
              reply);
        },
        reply);
  };
}

std::optional<drafts::Pattern> onePattern(const Item& it,
                                          const std::map<std::string, nlohmann::json>& pats,
                                          const std::string& size) {
  auto p = pats.find(size);
  if (p == pats.end())
    return std::nullopt;
  return drafts::patternFromJsonValue(p->second,
                                      "item " + std::to_string(it.id) + " pattern " + size);
}

// GET /api/items/{id}/pattern.dxf
Response patternDxfFile(const Item& it, const std::optional<nlohmann::json>&,
                        const std::map<std::string, nlohmann::json>& pats,
                        const std::string& size) {
  auto p = onePattern(it, pats, size);
  if (!p)
    return noPatternForSize(it, size);
  return downloadResponse("application/dxf",
                          patternDxf(*p, {patternStyle(it), sizeLabel(it, size)}),
                          patternFileBase(it, size) + ".dxf");
}

// GET /api/items/{id}/pattern.pdf: tiled for office paper (A4 by default, US Letter) or on A0
// plotter pages.
void getPatternPdf(RouteContext* c, const Request& req, const RouteMatch& m, Reply reply) {
  const drafts::Paper paper = paperParam(m);
  patternRoute(
      c, [paper](const Item& it, const std::optional<nlohmann::json>&,
                 const std::map<std::string, nlohmann::json>& pats, const std::string& size) {
        auto p = onePattern(it, pats, size);
        if (!p)
          return noPatternForSize(it, size);
        return downloadResponse("application/pdf",
                                patternPdf(*p, {patternStyle(it), sizeLabel(it, size)}, paper),
                                patternFileBase(it, size) + "_" + paperFileTag(paper) + ".pdf");
      })(req, m, std::move(reply));
}

// GET /api/items/{id}/garmentcode.json
Response garmentCodeFile(const Item& it, const std::optional<nlohmann::json>&,
                         const std::map<std::string, nlohmann::json>& pats,
                         const std::string& size) {
  auto p = onePattern(it, pats, size);
  if (!p)
    return noPatternForSize(it, size);
  return downloadResponse("application/json",
                          garmentCodeJson(*p, {patternStyle(it), sizeLabel(it, size)}),
                          patternFileBase(it, size) + "_specification.json");
}

// Files of the item's graded size run; an item whose garment could not be drafted says why.
Handler gradedRoute(RouteContext* c, GradedWrite write) {
  return patternRoute(
      c, [write](const Item& it, const std::optional<nlohmann::json>& guide,
                 const std::map<std::string, nlohmann::json>& pats, const std::string&) {
        if (pats.empty())
          return noDraftedPattern(it, "base");
        auto run = gradedRun(it, guide, pats);
        if (!run)
          return jsonError(http::status::not_found,
                           "item " + std::to_string(it.id) +
                               " has no graded size run (fewer than two graded sizes stored)");
        return write(it, *run);
      });
}

Response gradedDxfFile(const Item& it, const GradedRun& run) {
  return downloadResponse("application/dxf", gradedDxf(run), patternStyle(it) + ".dxf");
}

Response gradedRulFile(const Item& it, const GradedRun& run) {
  return downloadResponse("text/plain; charset=us-ascii", gradeRuleTable(run),
                          patternStyle(it) + ".rul");
}

// Nested grading: every size of the run superimposed per piece, the sample size marked.
Response nestedGradingSvgFile(const Item& it, const GradedRun& run) {
  return downloadResponse("image/svg+xml", drafts::nestedGradingSvg(run),
                          patternStyle(it) + "_nested_grading.svg");
}

Response nestedGradingPdfFile(const Item& it, const GradedRun& run) {
  return downloadResponse("application/pdf", drafts::nestedGradingPdf(run),
                          patternStyle(it) + "_nested_grading.pdf");
}

Response nestedGradingDxfFile(const Item& it, const GradedRun& run) {
  return downloadResponse("application/dxf", drafts::nestedGradingDxf(run),
                          patternStyle(it) + "_nested_grading.dxf");
}

// A marker of the sizes `q` asks for (default: the item's own) in `format`.
Response markerFile(MarkerFile format, const MarkerQuery& q, const Item& it,
                    const std::map<std::string, nlohmann::json>& pats) {
  if (pats.empty())
    return noDraftedPattern(it, "base");
  std::vector<std::string> sizes = q.sizes;
  if (sizes.empty())
    sizes.push_back(pats.count("base") || !pats.count(it.baseSize) ? "base" : it.baseSize);
  std::vector<drafts::SizedPattern> sized;
  std::string labels;
  for (const auto& s : sizes) {
    if (!pats.count(s)) {
      if (q.sizes.empty())
        return noPatternForSize(it, s);
      std::string have;
      for (const auto& h : it.sizes)
        have += (have.empty() ? "" : ", ") + h;
      return jsonError(http::status::bad_request, "query 'sizes': item " + std::to_string(it.id) +
                                                      " has no pattern for size '" + s +
                                                      "' (sizes: " + have + ")");
    }
    if (patternIsEmpty(pats.at(s)))
      return noDraftedPattern(it, s);
    // The piece as measured keeps the name "base" beside its own chart size.
    const bool both =
        s == "base" && std::find(sizes.begin(), sizes.end(), it.baseSize) != sizes.end();
    sized.push_back({both ? s : sizeLabel(it, s), *onePattern(it, pats, s)});
    labels += (labels.empty() ? "" : "-") + sized.back().size;
  }
  drafts::Marker laid;
  try {
    laid = drafts::layMarker(sized, {q.widthCm, drafts::MarkerOptions{}.gapCm, q.maxPieces});
  } catch (const drafts::MarkerLimitError& e) {
    return jsonError(http::status::unprocessable_entity,
                     std::string(e.what()) + " (the station's [marker] max_pieces is " +
                         std::to_string(q.maxPieces) + ")");
  }
  std::string title = patternStyle(it) + " " + sized.front().pattern.type + " size";
  for (const auto& sp : sized)
    title += " " + sp.size;
  const std::string name =
      patternFileBase(it, "marker_" + labels + "_" + widthTag(q.widthCm) + "cm");
  switch (format) {
    case MarkerFile::kSvg:
      return downloadResponse("image/svg+xml", drafts::markerSvg(laid, title), name + ".svg");
    case MarkerFile::kPdf:
      return downloadResponse("application/pdf", drafts::markerPdf(laid, title), name + ".pdf");
    case MarkerFile::kDxf:
      return downloadResponse("application/dxf", drafts::markerDxf(laid), name + ".dxf");
    case MarkerFile::kJson:
      break;
  }
  return jsonResponse(http::status::ok, drafts::markerSummaryJson(laid, title));
}

// Markers: every piece of the sizes asked for (default: the item's own) laid on the fabric
// width. A marker that cannot be laid (a piece wider than the fabric) is a 422 naming why.
// One marker at a time per station (kMaxMarkersAtOnce): a request that finds the slot taken
// gets 503 with Retry-After; the slot is freed as the answer is sent (or the request is
// dropped).
Handler markerRoute(RouteContext* c, std::shared_ptr<MarkerSlots> markerSlots, MarkerFile format) {
  return [=](const Request& req, const RouteMatch& m, Reply reply) {
    MarkerQuery q = markerQuery(m);
    q.maxPieces = c->markerMaxPieces();
    const auto slot = markerSlots->tryAcquire();
    if (!slot)
      return reply(markerBusy());
    Reply answer = [slot, reply](Response r) {
      slot->release();
      reply(std::move(r));
    };
    patternRoute(c, [format, q](const Item& it, const std::optional<nlohmann::json>&,
                                const std::map<std::string, nlohmann::json>& pats,
                                const std::string&) { return markerFile(format, q, it, pats); })(
        req, m, std::move(answer));
  };
}

// GET /api/items/{id}/measurements.vit: the body the draft was made for, as Valentina reads it.
Response measurementsVitFile(const Item& it, const std::optional<nlohmann::json>&,
                             const std::map<std::string, nlohmann::json>& pats,
                             const std::string&) {
  auto base = pats.find("base");
  auto m = vitMeasurements(it, base == pats.end() ? std::nullopt : std::optional(base->second));
  if (m.empty())
    return jsonError(http::status::not_found,
                     "item " + std::to_string(it.id) + " has no body measurements Valentina knows");
  return downloadResponse("application/xml", drafts::measurementsToVit(m),
                          patternFileBase(it, "body") + ".vit");
}

}  // namespace

void addExportRoutes(Router& router, RouteContext& ctx) {
  using V = http::verb;
  RouteContext* c = &ctx;
  router.add(V::get, "/api/export/shopify.csv",
             shopFileRoute(c, "shopify.csv", "text/csv; charset=utf-8", shopifyCsv));
  router.add(V::get, "/api/export/woocommerce.csv",
             shopFileRoute(c, "woocommerce.csv", "text/csv; charset=utf-8", wooCommerceCsv));
  router.add(
      V::get, "/api/export/merchant.tsv",
      shopFileRoute(c, "merchant.tsv", "text/tab-separated-values; charset=utf-8", merchantTsv));
  router.add(V::get, "/api/export/catalog.zip", withContext(c, getCatalogZip));
  router.add(V::get, "/api/export/files/images/{name}.jpg", exportImageRoute(c, "jpg"));
  router.add(V::get, "/api/export/files/images/{name}.png", exportImageRoute(c, "png"));
  router.add(V::get, "/api/export/files/images/{name}.webp", exportImageRoute(c, "webp"));
  router.add(V::get, "/api/size_charts/{name}.vst", getSizeChartVst);
  router.add(V::get, "/api/items/{id}/pattern.dxf", patternRoute(c, patternDxfFile));
  router.add(V::get, "/api/items/{id}/pattern.pdf", withContext(c, getPatternPdf));
  router.add(V::get, "/api/items/{id}/garmentcode.json", patternRoute(c, garmentCodeFile));
  router.add(V::get, "/api/items/{id}/pattern_graded.dxf", gradedRoute(c, gradedDxfFile));
  router.add(V::get, "/api/items/{id}/pattern_graded.rul", gradedRoute(c, gradedRulFile));
  router.add(V::get, "/api/items/{id}/nested_grading.svg", gradedRoute(c, nestedGradingSvgFile));
  router.add(V::get, "/api/items/{id}/nested_grading.pdf", gradedRoute(c, nestedGradingPdfFile));
  router.add(V::get, "/api/items/{id}/nested_grading.dxf", gradedRoute(c, nestedGradingDxfFile));
  const auto markerSlots = std::make_shared<MarkerSlots>();
  router.add(V::get, "/api/items/{id}/marker.svg", markerRoute(c, markerSlots, MarkerFile::kSvg));
  router.add(V::get, "/api/items/{id}/marker.pdf", markerRoute(c, markerSlots, MarkerFile::kPdf));
  router.add(V::get, "/api/items/{id}/marker.dxf", markerRoute(c, markerSlots, MarkerFile::kDxf));
  router.add(V::get, "/api/items/{id}/marker.json", markerRoute(c, markerSlots, MarkerFile::kJson));
  router.add(V::get, "/api/items/{id}/measurements.vit", patternRoute(c, measurementsVitFile));
}

}  // namespace garmcap::daemon
