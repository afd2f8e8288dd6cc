// The tape-measure routes (daemon/tape.h has the API). Validation happens twice on purpose: the
// body's shape before the strand is entered, the item-dependent checks on the strand, where the
// item cannot change between the check and the write.

#include <cmath>

#include "garmcap/daemon/http_router.h"
#include "garmcap/daemon/station_routes.h"
#include "garmcap/daemon/tape.h"
#include "garmcap/daemon/utf8.h"
#include "garmcap/drafts/garment_vocabulary.h"
#include "garmcap/pipeline/garment_measurer.h"

namespace garmcap::daemon {

namespace {
// A type has at most a dozen measurements; the cap only bounds the work a request can ask for.
constexpr std::size_t kMaxTapeNames = 32;

bool measurementName(const std::string& k) {
  return !k.empty() && k.size() <= 64 && std::all_of(k.begin(), k.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
}
}  // namespace

TapeRequest parseTapeRequest(const nlohmann::json& body) {
  if (!body.is_object())
    throw BadRequest(R"(the body must be {"item": id, "measurements": {"name": cm, ...}})");
  for (const auto& [k, v] : body.items())
    if (k != "item" && k != "measurements")
      throw BadRequest("unknown field '" + quoteInput(k) + "'");
  TapeRequest r;
  const auto item = body.find("item");
  if (item == body.end() || !item->is_number_integer() || item->get<std::int64_t>() <= 0)
    throw BadRequest("field 'item' must be an item id (a positive integer)");
  r.itemId = item->get<std::int64_t>();
  const auto ms = body.find("measurements");
  if (ms == body.end() || !ms->is_object() || ms->empty())
    throw BadRequest("field 'measurements' must be an object name -> cm with at least one name");
  if (ms->size() > kMaxTapeNames)
    throw BadRequest("field 'measurements' holds " + std::to_string(ms->size()) +
                     " names; at most " + std::to_string(kMaxTapeNames));
  for (const auto& [k, v] : ms->items()) {
    if (!validUtf8(k) || !measurementName(k))
      throw BadRequest("measurement name '" + quoteInput(k) + "' is not a measurement name");
    if (!v.is_number() || !std::isfinite(v.get<double>()) || !(v.get<double>() > 0) ||
        v.get<double>() > kMaxTapeCm)
      throw BadRequest("measurements." + k + " must be a number of cm in (0, " +
                       std::to_string(static_cast<int>(kMaxTapeCm)) + "]");
    r.tapeCm[k] = v.get<double>();
  }
  return r;
}

std::vector<TapeEntry> tapeEntriesFor(Catalog& catalog, const TapeRequest& request) {
  const auto item = catalog.item(request.itemId);
  if (!item)
    throw BadRequest("field 'item': no item " + std::to_string(request.itemId));
  if (item->type.empty())
    throw BadRequest("field 'item': item " + std::to_string(item->id) +
                     " has no garment type; set its type before taping it");
  const auto& names = drafts::garmentMeasurementNames(item->type);
  const auto result = catalog.result(item->id);
  std::vector<TapeEntry> out;
  for (const auto& [name, tape] : request.tapeCm) {
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      std::string list;
      for (const auto& n : names)
        list += (list.empty() ? "" : ", ") + n;
      throw BadRequest("measurements." + name + ": a " + item->type + " has no '" + name +
                       "' (it has " + list + ")");
    }
    // The pipeline's own reading, uncorrected: that is what later captures are corrected from.
    // A staff edit of the stored value is not a reading of the method.
    std::optional<double> measured;
    if (result)
      measured = pipeline::rawMeasurement(*result, name);
    if (!measured) {
      const auto m = item->measurementsCm.find(name);
      if (m != item->measurementsCm.end())
        measured = m->second;
    }
    if (!measured || !std::isfinite(*measured) || !(*measured > 0))
      throw BadRequest("measurements." + name + ": item " + std::to_string(item->id) +
                       " was not measured for " + name +
                       " by its capture, so there is nothing to correct");
    TapeEntry e;
    e.itemId = item->id;
    e.name = name;
    e.type = item->type;
    e.tapeCm = tape;
    e.measuredCm = *measured;
    out.push_back(std::move(e));
  }
  return out;
}

pipeline::CorrectionTable tapeCorrections(Catalog& catalog) {
  std::vector<pipeline::TapeRecord> records;
  for (const auto& t : catalog.tapes())
    records.push_back({t.type, t.name, t.measuredCm, t.tapeCm});
  return pipeline::fitCorrections(records);
}

nlohmann::json tapeRowsJson(const std::vector<TapeEntry>& rows) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& t : rows)
    out.push_back({{"item", t.itemId},
                   {"type", t.type},
                   {"measurement", t.name},
                   {"tape_cm", t.tapeCm},
                   {"measured_cm", t.measuredCm},
                   {"created_at", t.createdAt}});
  return out;
}

void addTapeRoutes(Router& router, RouteContext& ctx) {
  RouteContext* c = &ctx;
  using V = http::verb;
  router.add(V::get, "/api/tape", [c](const Request&, const RouteMatch&, Reply reply) {
    c->withCatalog(
        [reply](Catalog& cat) {
          reply(jsonResponse(http::status::ok,
                             {{"tape", tapeRowsJson(cat.tapes())},
                              {"corrections", pipeline::correctionTableJson(tapeCorrections(cat))},
                              {"min_pairs_offset", pipeline::kMinPairsForOffset},
                              {"min_pairs_scale", pipeline::kMinPairsForScale}}));
        },
        reply);
  });
  router.add(V::post, "/api/tape", [c](const Request& req, const RouteMatch&, Reply reply) {
    const TapeRequest request = parseTapeRequest(parseJsonBody(req));
    c->withCatalog(
        [reply, request](Catalog& cat) {
          cat.setTape(request.itemId, tapeEntriesFor(cat, request));
          reply(
              jsonResponse(http::status::ok,
                           {{"item", request.itemId},
                            {"tape", tapeRowsJson(cat.tapes(request.itemId))},
                            {"corrections", pipeline::correctionTableJson(tapeCorrections(cat))}}));
        },
        reply);
  });
  router.add(V::delete_, "/api/tape/{item}", [c](const Request&, const RouteMatch& m, Reply reply) {
    const auto id = m.id("item");
    c->withCatalog(
        [reply, id](Catalog& cat) {
          const int n = cat.deleteTape(id);
          if (n == 0)
            return reply(jsonError(http::status::not_found,
                                   "item " + std::to_string(id) + " has no tape measurements"));
          reply(
              jsonResponse(http::status::ok,
                           {{"deleted", n},
                            {"corrections", pipeline::correctionTableJson(tapeCorrections(cat))}}));
        },
        reply);
  });
}

}  // namespace garmcap::daemon
