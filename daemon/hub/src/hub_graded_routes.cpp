#include "garmcap/hub/hub_graded_routes.h"

#include <functional>

#include "garmcap/daemon/export_catalog.h"
#include "garmcap/daemon/export_items.h"
#include "garmcap/drafts/export_dxf_aama.h"
#include "garmcap/drafts/export_garmentcode.h"
#include "garmcap/drafts/export_nested_grading.h"
#include "garmcap/drafts/export_rul.h"
#include "garmcap/drafts/file_io.h"
#include "garmcap/drafts/measurements.h"
#include "garmcap/drafts/pattern_io.h"
#include "garmcap/hub/hub_exports.h"

namespace garmcap::hub {

namespace http = daemon::http;
using daemon::jsonError;
using daemon::Reply;
using daemon::Request;
using daemon::Response;
using daemon::RouteMatch;

namespace {

// What the graded routes work from: the item as the export writers take it (hub id, the hub's
// title and price, the station's base size and sizes), its size guide and stored patterns.
struct StoredItem {
  daemon::Item item;
  std::optional<nlohmann::json> guide;
  std::map<std::string, nlohmann::json> patterns;
};

using Write = std::function<Response(const StoredItem&, const RouteMatch&)>;

// A pattern with no pieces is what a station stores for a garment it could not draft.
bool noPieces(const nlohmann::json& p) {
  const auto panels = p.find("panels");
  return !p.is_object() || panels == p.end() || !panels->is_array() || panels->empty();
}

Response notDrafted(const daemon::Item& it, const std::string& size) {
  return jsonError(http::status::unprocessable_entity,
                   "item " + std::to_string(it.id) + " size '" + size +
                       "': the stored pattern has no pieces (its garment could not be drafted)");
}

Response noPattern(const daemon::Item& it, const std::string& size) {
  std::string have;
  for (const auto& s : it.sizes)
    have += (have.empty() ? "" : ", ") + s;
  return jsonError(
      http::status::not_found,
      "item " + std::to_string(it.id) + " has no pattern for size '" + size + "'" +
          (have.empty() ? " (its station sent no pattern)" : " (sizes: " + have + ")"));
}

// The files of the item's graded run (every stored size but "base", in size-guide order); an
// item with fewer than two graded sizes has none (404), as at the station.
Write graded(std::function<Response(const daemon::Item&, const drafts::GradedRun&)> write) {
  return [write](const StoredItem& s, const RouteMatch&) {
    if (s.patterns.empty())
      return noPattern(s.item, "base");
    for (const auto& [size, p] : s.patterns)
      if (size != "base" && noPieces(p))
        return notDrafted(s.item, size);
    const auto run = daemon::gradedRun(s.item, s.guide, s.patterns);
    if (!run)
      return jsonError(http::status::not_found,
                       "item " + std::to_string(s.item.id) +
                           " has no graded size run (fewer than two graded sizes stored)");
    return write(s.item, *run);
  };
}

}  // namespace

void addHubGradedRoutes(daemon::Router& router, HubStore& store, const HubConfig& config,
                        const HubLogins* logins) {
  // The item the caller may read with its patterns, then `write`; a pattern a writer refuses
  // (or cannot parse) is a 422 naming why.
  auto route = [&store, &config, logins](Write write) {
    return [&store, &config, logins, write](const Request& req, const RouteMatch& m, Reply reply) {
      const auto h = readableItem(req, m, store, config, logins, reply);
      if (!h)
        return;
      StoredItem s{catalogItemOf(*h), sizeGuideOf(*h), store.patterns(h->id)};
      s.item.sizes = h->patternSizes;
      try {
        reply(write(s, m));
      } catch (const drafts::PatternExportError& e) {
        reply(jsonError(http::status::unprocessable_entity, e.what()));
      } catch (const drafts::ParseError& e) {
        reply(jsonError(http::status::unprocessable_entity, e.what()));
      }
    };
  };

  router.add(http::verb::get, "/api/items/{id}/pattern_graded.dxf",
             route(graded([](const daemon::Item& it, const drafts::GradedRun& run) {
               return daemon::downloadResponse("application/dxf", drafts::gradedDxf(run),
                                               daemon::patternStyle(it) + ".dxf");
             })));
  router.add(http::verb::get, "/api/items/{id}/pattern_graded.rul",
             route(graded([](const daemon::Item& it, const drafts::GradedRun& run) {
               return daemon::downloadResponse("text/plain; charset=us-ascii",
                                               drafts::gradeRuleTable(run),
                                               daemon::patternStyle(it) + ".rul");
             })));
  router.add(http::verb::get, "/api/items/{id}/nested_grading.svg",
             route(graded([](const daemon::Item& it, const drafts::GradedRun& run) {
               return daemon::downloadResponse("image/svg+xml", drafts::nestedGradingSvg(run),
                                               daemon::patternStyle(it) + "_nested_grading.svg");
             })));
  router.add(http::verb::get, "/api/items/{id}/nested_grading.pdf",
             route(graded([](const daemon::Item& it, const drafts::GradedRun& run) {
               return daemon::downloadResponse("application/pdf", drafts::nestedGradingPdf(run),
                                               daemon::patternStyle(it) + "_nested_grading.pdf");
             })));
  router.add(http::verb::get, "/api/items/{id}/nested_grading.dxf",
             route(graded([](const daemon::Item& it, const drafts::GradedRun& run) {
               return daemon::downloadResponse("application/dxf", drafts::nestedGradingDxf(run),
                                               daemon::patternStyle(it) + "_nested_grading.dxf");
             })));

  router.add(http::verb::get, "/api/items/{id}/garmentcode.json",
             route([](const StoredItem& s, const RouteMatch& m) {
               const std::string size = daemon::patternSizeParam(m);
               const auto p = s.patterns.find(size);
               if (p == s.patterns.end())
                 return noPattern(s.item, size);
               if (noPieces(p->second))
                 return notDrafted(s.item, size);
               const auto pattern = drafts::patternFromJsonValue(
                   p->second, "item " + std::to_string(s.item.id) + " pattern " + size);
               return daemon::downloadResponse(
                   "application/json",
                   drafts::garmentCodeJson(
                       pattern, {daemon::patternStyle(s.item), daemon::sizeLabel(s.item, size)}),
                   daemon::patternFileBase(s.item, size) + "_specification.json");
             }));

  router.add(http::verb::get, "/api/items/{id}/measurements.vit",
             route([](const StoredItem& s, const RouteMatch&) {
               const auto base = s.patterns.find("base");
               const auto body = daemon::vitMeasurements(
                   s.item, base == s.patterns.end() || noPieces(base->second)
                               ? std::nullopt
                               : std::optional(base->second));
               if (body.empty())
                 return jsonError(http::status::not_found,
                                  "item " + std::to_string(s.item.id) +
                                      " has no body measurements Valentina knows");
               return daemon::downloadResponse("application/xml", drafts::measurementsToVit(body),
                                               daemon::patternFileBase(s.item, "body") + ".vit");
             }));
}

}  // namespace garmcap::hub
