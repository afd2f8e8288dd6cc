#include "garmcap/hub/hub_pattern_routes.h"

#include <algorithm>

#include "garmcap/daemon/export_catalog.h"
#include "garmcap/daemon/export_items.h"
#include "garmcap/daemon/utf8.h"
#include "garmcap/drafts/export_dxf_aama.h"
#include "garmcap/drafts/export_pdf.h"
#include "garmcap/drafts/export_svg.h"
#include "garmcap/drafts/file_io.h"
#include "garmcap/drafts/pattern_io.h"
#include "garmcap/hub/hub_caller.h"
#include "garmcap/hub/hub_exports.h"

namespace garmcap::hub {

namespace http = daemon::http;
using daemon::BadRequest;
using daemon::jsonError;
using daemon::jsonResponse;
using daemon::Reply;
using daemon::Request;
using daemon::Response;
using daemon::RouteMatch;

namespace {

// Sizes as the hub's item_patterns table takes them (and the station names them).
bool validSize(const std::string& s) {
  return !s.empty() && s.size() <= 32 && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
}

// What a pattern route writes from one stored pattern.
using PatternWrite = std::function<Response(const daemon::Item&, const drafts::Pattern&,
                                            const std::string& size, const RouteMatch&)>;

}  // namespace

std::optional<std::map<std::string, nlohmann::json>> pushedPatterns(const nlohmann::json& body) {
  if (!body.contains("patterns") || body["patterns"].is_null())
    return std::nullopt;
  const auto& p = body["patterns"];
  if (!p.is_object())
    throw BadRequest("patterns must be an object of size -> pattern JSON");
  std::map<std::string, nlohmann::json> out;
  for (const auto& [size, pattern] : p.items()) {
    if (!validSize(size))
      throw BadRequest("patterns: size '" + daemon::quoteInput(size) +
                       "' must be 1..32 of [A-Za-z0-9_-]");
    if (!pattern.is_object())
      throw BadRequest("patterns." + size + " must be a pattern object");
    out[size] = pattern;
  }
  return out;
}

void addHubPatternRoutes(daemon::Router& router, HubStore& store, const HubConfig& config,
                         const HubLogins* logins) {
  // The item the caller may read (admin: any; a station: its own), not deleted; else a 404
  // reply, sent, and nullopt.
  auto readableItem = [&store, &config, logins](const Request& req, const RouteMatch& m,
                                                const Reply& reply) {
    return hub::readableItem(req, m, store, config, logins, reply);
  };

  router.add(
      http::verb::get, "/api/items/{id}/patterns",
      [readableItem](const Request& req, const RouteMatch& m, Reply reply) {
        const auto it = readableItem(req, m, reply);
        if (it)
          reply(jsonResponse(http::status::ok, {{"id", it->id}, {"sizes", it->patternSizes}}));
      });

  // One stored pattern, parsed by the drafts library, written by `write`. A size the item has
  // no pattern of is a 404 naming the sizes it has; a pattern the writer refuses, a 422.
  auto patternRoute = [&store, readableItem](PatternWrite write) {
    return [&store, readableItem, write](const Request& req, const RouteMatch& m, Reply reply) {
      const std::string size = daemon::patternSizeParam(m);
      const auto h = readableItem(req, m, reply);
      if (!h)
        return;
      const auto json = store.pattern(h->id, size);
      if (!json) {
        std::string have;
        for (const auto& s : h->patternSizes)
          have += (have.empty() ? "" : ", ") + s;
        return reply(jsonError(
            http::status::not_found,
            "item " + std::to_string(h->id) + " has no pattern for size '" + size + "'" +
                (have.empty() ? " (its station sent no pattern)" : " (sizes: " + have + ")")));
      }
      daemon::Item it = catalogItemOf(*h);
      it.sizes = h->patternSizes;
      try {
        const auto p = drafts::patternFromJsonValue(
            *json, "item " + std::to_string(h->id) + " pattern " + size);
        if (p.panels.empty())
          return reply(jsonError(http::status::unprocessable_entity,
                                 "item " + std::to_string(h->id) + " size '" + size +
                                     "': the stored pattern has no pieces (its garment could "
                                     "not be drafted)"));
        reply(write(it, p, size, m));
      } catch (const drafts::PatternExportError& e) {
        reply(jsonError(http::status::unprocessable_entity, e.what()));
      } catch (const drafts::ParseError& e) {
        reply(jsonError(http::status::unprocessable_entity, e.what()));
      }
    };
  };

  router.add(http::verb::get, "/api/items/{id}/pattern.json",
             [&store, readableItem](const Request& req, const RouteMatch& m, Reply reply) {
               const std::string size = daemon::patternSizeParam(m);
               const auto h = readableItem(req, m, reply);
               if (!h)
                 return;
               auto json = store.pattern(h->id, size);
               if (!json)
                 return reply(jsonError(
                     http::status::not_found,
                     "item " + std::to_string(h->id) + " has no pattern for size '" + size + "'"));
               reply(jsonResponse(http::status::ok, *json));
             });
  router.add(http::verb::get, "/api/items/{id}/pattern.svg",
             patternRoute([](const daemon::Item& it, const drafts::Pattern& p,
                             const std::string& size, const RouteMatch&) {
               return daemon::downloadResponse(
                   "image/svg+xml",
                   drafts::patternSvg(p, {daemon::patternStyle(it), daemon::sizeLabel(it, size)}),
                   daemon::patternFileBase(it, size) + ".svg");
             }));
  router.add(http::verb::get, "/api/items/{id}/pattern.dxf",
             patternRoute([](const daemon::Item& it, const drafts::Pattern& p,
                             const std::string& size, const RouteMatch&) {
               return daemon::downloadResponse(
                   "application/dxf",
                   drafts::patternDxf(p, {daemon::patternStyle(it), daemon::sizeLabel(it, size)}),
                   daemon::patternFileBase(it, size) + ".dxf");
             }));
  router.add(
      http::verb::get, "/api/items/{id}/pattern.pdf",
      patternRoute([](const daemon::Item& it, const drafts::Pattern& p, const std::string& size,
                      const RouteMatch& m) {
        const drafts::Paper paper = daemon::paperParam(m);
        return daemon::downloadResponse(
            "application/pdf",
            drafts::patternPdf(p, {daemon::patternStyle(it), daemon::sizeLabel(it, size)}, paper),
            daemon::patternFileBase(it, size) + "_" + daemon::paperFileTag(paper) + ".pdf");
      }));
}

}  // namespace garmcap::hub
