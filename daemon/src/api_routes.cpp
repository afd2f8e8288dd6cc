// The station's JSON API (docs/api.md). Handlers validate everything that comes from the request
// (ids, query values, JSON fields) and reach data only through the catalog and the content store
// by id/sha, never by a path taken from the request.

#include "garmcap/daemon/api_routes.h"

#include <spdlog/spdlog.h>

#include <charconv>
#include <set>
#include <sstream>

#include "garmcap/daemon/capture_processor.h"
#include "garmcap/daemon/catalog.h"
#include "garmcap/daemon/content_store.h"
#include "garmcap/daemon/export_shop.h"
#include "garmcap/daemon/http_guard.h"
#include "garmcap/drafts/pattern_io.h"
#include "garmcap/drafts/svg.h"
#include "garmcap/dsw/size_guide.h"

namespace garmcap::daemon {

namespace {

const std::set<std::string> kTypes = {"", "top", "dress", "skirt", "pants"};

bool validSku(const std::string& s) {
  if (s.size() > 64)
    return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-'))
      return false;
  return true;
}

int queryInt(const RouteMatch& m, const std::string& name, int fallback, int lo, int hi) {
  auto v = m.queryValue(name);
  if (!v)
    return fallback;
  int x = 0;
  const auto [p, ec] = std::from_chars(v->data(), v->data() + v->size(), x);
  if (ec != std::errc() || p != v->data() + v->size() || x < lo || x > hi)
    throw BadRequest("query '" + name + "' must be an integer in " + std::to_string(lo) + ".." +
                     std::to_string(hi) + ", got '" + quoteInput(*v) + "'");
  return x;
}

// Text that reaches the catalog, the shop CSVs and the pattern files: the JSON parser has
// already refused invalid UTF-8; control characters are refused here (a NUL would cut a title
// short in C strings, a CR would split a CSV row in a careless importer). Notes keep newlines
// and tabs.
void requireText(const std::string& s, const std::string& what, bool multiLine = false) {
  if (!validUtf8(s))
    throw BadRequest(what + " is not valid UTF-8");
  for (unsigned char c : s)
    if ((c < 0x20 && !(multiLine && (c == '\n' || c == '\t' || c == '\r'))) || c == 0x7F)
      throw BadRequest(what + " holds a control character (byte " + std::to_string(c) + ")");
}

std::string requireStringField(const nlohmann::json& body, const std::string& key,
                               std::size_t maxLen, bool multiLine = false) {
  const auto& v = body.at(key);
  if (!v.is_string())
    throw BadRequest("field '" + key + "' must be a string");
  std::string s = v.get<std::string>();
  if (s.size() > maxLen)
    throw BadRequest("field '" + key + "' is longer than " + std::to_string(maxLen) + " bytes");
  requireText(s, "field '" + key + "'", multiLine);
  return s;
}

// An item as the API serves it: its stored fields and `default_title`, the title the shops get
// while staff leave it empty, so the web UI shows the exports' rule instead of a copy of it.
nlohmann::json itemJson(const Item& it) {
  nlohmann::json j = it.toJson();
  j["default_title"] = defaultProductTitle(it.type, it.attributes);
  return j;
}

ItemPatch parsePatch(const nlohmann::json& body) {
  if (!body.is_object())
    throw BadRequest("the PATCH body must be a JSON object");
  ItemPatch p;
  for (const auto& [key, value] : body.items()) {
    if (key == "sku") {
      p.sku = requireStringField(body, key, 64);
      if (!validSku(*p.sku))
        throw BadRequest("field 'sku' may hold only A-Z a-z 0-9 . _ -");
    } else if (key == "title") {
      p.title = requireStringField(body, key, 200);
    } else if (key == "notes") {
      p.notes = requireStringField(body, key, 4000, true);
    } else if (key == "status") {
      p.status = requireStringField(body, key, 32);
      if (*p.status != kStatusNeedsReview && *p.status != kStatusApproved &&
          *p.status != kStatusRejected)
        throw BadRequest("field 'status' must be needs_review, approved or rejected");
    } else if (key == "type") {
      p.type = requireStringField(body, key, 16);
      if (!kTypes.count(*p.type))
        throw BadRequest("field 'type' must be top, dress, skirt or pants");
    } else if (key == "price_cents") {
      if (value.is_null())
        p.priceCents = std::optional<std::int64_t>();
      else if (value.is_number_integer() && value.get<std::int64_t>() >= 0)
        p.priceCents = std::optional<std::int64_t>(value.get<std::int64_t>());
      else
        throw BadRequest("field 'price_cents' must be a non-negative integer or null");
    } else if (key == "tags") {
      if (!value.is_array() || value.size() > 50)
        throw BadRequest("field 'tags' must be an array of at most 50 strings");
      std::vector<std::string> tags;
      for (const auto& t : value) {
        if (!t.is_string() || t.get<std::string>().size() > 64)
          throw BadRequest("field 'tags' must hold strings of at most 64 bytes");
        requireText(t.get<std::string>(), "a tag");
        tags.push_back(t.get<std::string>());
      }
      p.tags = tags;
    } else if (key == "attributes") {
      if (!value.is_object() || value.size() > 50)
        throw BadRequest("field 'attributes' must be an object of strings");
      std::map<std::string, std::string> attrs;
      for (const auto& [k, v] : value.items()) {
        if (!v.is_string() || k.size() > 64 || v.get<std::string>().size() > 200)
          throw BadRequest("attribute '" + quoteInput(k) +
                           "' must be a string of at most 200 bytes under a name of at most 64");
        requireText(k, "an attribute name");
        requireText(v.get<std::string>(), "attribute '" + quoteInput(k) + "'");
        attrs[k] = v.get<std::string>();
      }
      p.attributes = attrs;
    } else if (key == "measurements") {
      // The vocabulary has a few dozen names; 100 is room for any garment, not for 50,000 rows.
      constexpr std::size_t kMaxMeasurements = 100;
      if (!value.is_object())
        throw BadRequest("field 'measurements' must be an object name -> cm");
      if (value.size() > kMaxMeasurements)
        throw BadRequest("field 'measurements' holds " + std::to_string(value.size()) +
                         " names; at most " + std::to_string(kMaxMeasurements));
      std::map<std::string, double> ms;
      for (const auto& [k, v] : value.items()) {
        if (k.empty() || k.size() > 64 || !std::all_of(k.begin(), k.end(), [](char c) {
              return std::islower(static_cast<unsigned char>(c)) ||
                     std::isdigit(static_cast<unsigned char>(c)) || c == '_';
            }))
          throw BadRequest("measurement name '" + quoteInput(k) + "' is not a measurement name");
        if (!v.is_number() || !(v.get<double>() > 0 && v.get<double>() < 1000))
          throw BadRequest("measurement '" + k + "' must be a number of cm in (0, 1000)");
        ms[k] = v.get<double>();
      }
      p.measurementsCm = ms;
    } else {
      throw BadRequest("unknown field '" + quoteInput(key) + "'");
    }
  }
  return p;
}

Response accepted(const SubmitResult& r) {
  if (!r.jobId) {
    const auto status = static_cast<http::status>(r.httpStatus);
    return jsonError(status, r.error);
  }
  nlohmann::json body{{"job", *r.jobId}};
  if (r.merged)
    body["merged"] = true;
  Response res = jsonResponse(http::status::accepted, body);
  res.set(http::field::location, "/api/jobs/" + std::to_string(*r.jobId));
  return res;
}

}  // namespace

Response noPatternForSize(const Item& item, const std::string& size) {
  if (item.sizes.empty())
    return noDraftedPattern(item, size);
  std::string have;
  for (const auto& s : item.sizes)
    have += (have.empty() ? "" : ", ") + s;
  return jsonError(http::status::not_found,
                   "item " + std::to_string(item.id) + " has no pattern for size '" + size + "'" +
                       (have.empty() ? " (it has no pattern at all)" : " (sizes: " + have + ")"));
}

Response noDraftedPattern(const Item& item, const std::string& size) {
  std::string why, all;
  for (const auto& w : item.warnings) {
    all += (all.empty() ? "" : "; ") + w;
    if (w.rfind(kNoPatternWarning, 0) == 0)
      why += (why.empty() ? "" : "; ") + w.substr(std::string_view(kNoPatternWarning).size());
  }
  if (why.empty())
    why = all.empty() ? "no reason recorded" : all;
  return jsonError(http::status::unprocessable_entity,
                   std::string(kNoPatternWarning) + why + " (item " + std::to_string(item.id) +
                       ", size '" + size + "': its garment could not be drafted)");
}

std::string sizeGuideCsv(const nlohmann::json& guide) {
  return dsw::sizeGuideCsv(dsw::sizeGuideFromJson(guide.dump(), "stored size guide"));
}

namespace {
// The item page shows the pieces to cut: cut line (solid) and sew line (dashed). The draft's
// own contours would lie on every sew line as a solid black line and hide its dashes.
drafts::SvgOptions itemSvgOptions() {
  drafts::SvgOptions o;
  o.drawDraft = false;
  return o;
}
}  // namespace

namespace {

// A named route handler bound to the station it serves (Router takes plain callables).
template <class Handler>
auto withStation(Station* st, Handler handler) {
  return [st, handler](auto&&... args) { handler(st, std::forward<decltype(args)>(args)...); };
}

// GET /api/status
void getStatus(Station* st, const Request&, const RouteMatch&, Reply reply) {
  st->status([reply](nlohmann::json s) { reply(jsonResponse(http::status::ok, s)); });
}

// POST /api/capture/empty
void postCaptureEmpty(Station* st, const Request&, const RouteMatch&, Reply reply) {
  st->submit(JobKind::kEmpty, "", 0, [reply](SubmitResult r) { reply(accepted(r)); });
}

// POST /api/capture
void postCapture(Station* st, const Request& req, const RouteMatch&, Reply reply) {
  std::string sku;
  if (!req.body().empty()) {
    const auto body = parseJsonBody(req);
    if (!body.is_object())
      throw BadRequest("the body must be a JSON object");
    for (const auto& [k, v] : body.items())
      if (k != "sku")
        throw BadRequest("unknown field '" + quoteInput(k) + "'");
    if (body.contains("sku")) {
      sku = requireStringField(body, "sku", 64);
      if (!validSku(sku))
        throw BadRequest("field 'sku' may hold only A-Z a-z 0-9 . _ -");
    }
  }
  st->submit(JobKind::kDressed, sku, 0, [reply](SubmitResult r) { reply(accepted(r)); });
}

// POST /api/button
void postButton(Station* st, const Request&, const RouteMatch&, Reply reply) {
  st->press([reply](SubmitResult r) { reply(accepted(r)); });
}

// GET /api/jobs/{id}
void getJobsById(Station* st, const Request&, const RouteMatch& m, Reply reply) {
  const auto id = m.id("id");
  st->job(id, [reply, id](std::optional<nlohmann::json> j) {
    reply(j ? jsonResponse(http::status::ok, *j)
            : jsonError(http::status::not_found, "no job " + std::to_string(id)));
  });
}

// GET /api/jobs
void getJobs(Station* st, const Request&, const RouteMatch& m, Reply reply) {
  const int limit = queryInt(m, "limit", 20, 1, 200);
  st->withCatalog(
      [reply, limit](Catalog& c) {
        nlohmann::json jobs = nlohmann::json::array();
        for (const auto& j : c.recentJobs(limit))
          jobs.push_back(j.toJson());
        reply(jsonResponse(http::status::ok, {{"jobs", jobs}}));
      },
      reply);
}

// GET /api/events
void getEvents(Station* st, const Request&, const RouteMatch&, std::shared_ptr<StreamSink> sink) {
  st->addEventSink(std::move(sink));
}

// GET /stream.mjpg
void getStreamMjpg(Station* st, const Request&, const RouteMatch&,
                   std::shared_ptr<StreamSink> sink) {
  st->addPreviewSink(std::move(sink));
}

// GET /api/items
void getItems(Station* st, const Request&, const RouteMatch& m, Reply reply) {
  ItemQuery q;
  q.search = m.queryValue("q").value_or("");
  if (q.search.size() > 200)
    throw BadRequest("query 'q' is longer than 200 bytes");
  q.type = m.queryValue("type").value_or("");
  if (!kTypes.count(q.type))
    throw BadRequest("query 'type' must be top, dress, skirt or pants");
  q.status = m.queryValue("status").value_or("");
  if (!q.status.empty() && q.status != kStatusNeedsReview && q.status != kStatusApproved &&
      q.status != kStatusRejected)
    throw BadRequest("query 'status' must be needs_review, approved or rejected");
  q.deleted = queryInt(m, "deleted", 0, 0, 1) == 1;
  q.offset = queryInt(m, "offset", 0, 0, 1 << 30);
  q.limit = queryInt(m, "limit", 50, 1, 500);
  st->withCatalog(
      [reply, q](Catalog& c) {
        auto [items, total] = c.items(q);
        nlohmann::json list = nlohmann::json::array();
        for (const auto& it : items)
          list.push_back(itemJson(it));
        reply(jsonResponse(
            http::status::ok,
            {{"items", list}, {"total", total}, {"offset", q.offset}, {"limit", q.limit}}));
      },
      reply);
}

// GET /api/items/{id}
void getItemsById(Station* st, const Request&, const RouteMatch& m, Reply reply) {
  const auto id = m.id("id");
  st->withCatalog(
      [reply, id](Catalog& c) {
        auto it = c.item(id);
        reply(it ? jsonResponse(http::status::ok, itemJson(*it))
                 : jsonError(http::status::not_found, "no item " + std::to_string(id)));
      },
      reply);
}

// PATCH /api/items/{id}
void patchItemsById(Station* st, const Request& req, const RouteMatch& m, Reply reply) {
  const auto id = m.id("id");
  const ItemPatch patch = parsePatch(parseJsonBody(req));
  st->withCatalog(
      [reply, id, patch](Catalog& c) {
        try {
          if (!c.patchItem(id, patch))
            return reply(jsonError(http::status::not_found, "no item " + std::to_string(id)));
          reply(jsonResponse(http::status::ok, itemJson(*c.item(id))));
        } catch (const CatalogError& e) {
          reply(jsonError(http::status::bad_request, e.what()));
        }
      },
      reply);
}

// DELETE /api/items/{id}
void deleteItemsById(Station* st, const Request&, const RouteMatch& m, Reply reply) {
  const auto id = m.id("id");
  st->withCatalog(
      [reply, id](Catalog& c) {
        reply(c.deleteItem(id)
                  ? jsonResponse(http::status::ok, {{"deleted", id}})
                  : jsonError(http::status::not_found, "no item " + std::to_string(id)));
      },
      reply);
}

// POST /api/items/{id}/restore
void postItemsByIdRestore(Station* st, const Request&, const RouteMatch& m, Reply reply) {
  const auto id = m.id("id");
  st->withCatalog(
      [reply, id](Catalog& c) {
        if (!c.restoreItem(id))
          return reply(jsonError(http::status::not_found, "no deleted item " + std::to_string(id)));
        reply(jsonResponse(http::status::ok, itemJson(*c.item(id))));
      },
      reply);
}

// POST /api/items/{id}/rerun
void postItemsByIdRerun(Station* st, const Request&, const RouteMatch& m, Reply reply) {
  const auto id = m.id("id");
  st->submit(JobKind::kRerun, "", id, [reply](SubmitResult r) { reply(accepted(r)); });
}

// POST /api/items/{id}/back
void postItemsByIdBack(Station* st, const Request&, const RouteMatch& m, Reply reply) {
  const auto id = m.id("id");
  st->submit(JobKind::kBack, "", id, [reply](SubmitResult r) { reply(accepted(r)); });
}

// GET /api/items/{id}/images/{kind}
void getItemsByIdImagesByKind(Station* st, const Request&, const RouteMatch& m, Reply reply) {
  const auto id = m.id("id");
  const std::string kind = m.param("kind");
  const bool download = m.queryValue("download").value_or("0") == "1";
  st->withCatalog(
      [st, reply, id, kind, download](Catalog& c) {
        auto it = c.item(id);
        if (!it)
          return reply(jsonError(http::status::not_found, "no item " + std::to_string(id)));
        auto im = std::find_if(it->images.begin(), it->images.end(),
                               [&](const ImageRef& r) { return r.kind == kind; });
        if (im == it->images.end())
          return reply(jsonError(http::status::not_found,
                                 "item " + std::to_string(id) + " has no image '" + kind + "'"));
        const std::string name =
            expandNamingTemplate(st->namingTemplate(), {{"sku", it->sku.empty() ? "item" : it->sku},
                                                        {"id", std::to_string(id)},
                                                        {"kind", kind},
                                                        {"type", it->type},
                                                        {"size", it->baseSize},
                                                        {"date", it->createdAt.substr(0, 10)}}) +
            (im->mediaType == "image/jpeg"   ? ".jpg"
             : im->mediaType == "image/webp" ? ".webp"
                                             : ".png");
        const ImageRef ref = *im;
        // Reading the blob happens off the strand: the catalog owner must not wait for disks.
        st->offload(
            [st, reply, ref, name, download] {
              auto bytes = st->store().read(ref.sha256);
              if (!bytes)
                return reply(jsonError(http::status::internal_server_error,
                                       "image " + ref.sha256 + " is missing from the store"));
              Response res = textResponse(http::status::ok, ref.mediaType, std::move(*bytes));
              res.set(http::field::cache_control, "private, max-age=31536000, immutable");
              res.set(http::field::etag, "\"" + ref.sha256 + "\"");
              res.set(
                  http::field::content_disposition,
                  std::string(download ? "attachment" : "inline") + "; filename=\"" + name + "\"");
              reply(std::move(res));
            },
            reply);
      },
      reply);
}

// GET /api/items/{id}/pattern.json
void getItemsByIdPatternJson(Station* st, const Request&, const RouteMatch& m, Reply reply) {
  const auto id = m.id("id");
  const std::string size = patternSizeParam(m);
  st->withCatalog(
      [reply, id, size](Catalog& c) {
        auto it = c.item(id);
        if (!it)
          return reply(jsonError(http::status::not_found, "no item " + std::to_string(id)));
        auto p = c.pattern(id, size);
        if (!p)
          return reply(noPatternForSize(*it, size));
        reply(patternIsEmpty(*p) ? noDraftedPattern(*it, size)
                                 : jsonResponse(http::status::ok, *p));
      },
      reply);
}

// GET /api/items/{id}/pattern.svg
void getItemsByIdPatternSvg(Station* st, const Request&, const RouteMatch& m, Reply reply) {
  const auto id = m.id("id");
  const std::string size = patternSizeParam(m);
  st->withCatalog(
      [st, reply, id, size](Catalog& c) {
        auto it = c.item(id);
        if (!it)
          return reply(jsonError(http::status::not_found, "no item " + std::to_string(id)));
        auto p = c.pattern(id, size);
        if (!p)
          return reply(noPatternForSize(*it, size));
        if (patternIsEmpty(*p))
          return reply(noDraftedPattern(*it, size));
        st->offload(
            [reply, json = *p, id, size] {
              try {
                const auto pattern = drafts::patternFromJsonValue(
                    json, "item " + std::to_string(id) + " pattern " + size);
                reply(textResponse(http::status::ok, "image/svg+xml",
                                   drafts::patternToSvg(pattern, itemSvgOptions())));
              } catch (const std::exception& e) {
                reply(jsonError(http::status::internal_server_error, e.what()));
              }
            },
            reply);
      },
      reply);
}

// The item's size guide as stored (JSON) or as the shopper's table (CSV).
void sizeGuide(Station* st, bool csv, const Request&, const RouteMatch& m, Reply reply) {
  const auto id = m.id("id");
  st->withCatalog(
      [reply, id, csv](Catalog& c) {
        if (!c.item(id))
          return reply(jsonError(http::status::not_found, "no item " + std::to_string(id)));
        auto g = c.sizeGuide(id);
        if (!g)
          return reply(jsonError(http::status::not_found,
                                 "item " + std::to_string(id) + " has no size guide (not graded)"));
        if (!csv)
          return reply(jsonResponse(http::status::ok, *g));
        try {
          reply(textResponse(http::status::ok, "text/csv; charset=utf-8", sizeGuideCsv(*g)));
        } catch (const std::exception& e) {
          reply(jsonError(http::status::internal_server_error,
                          std::string("stored size guide is malformed: ") + e.what()));
        }
      },
      reply);
}

// GET /api/items/{id}/sizeguide.json
void getItemsByIdSizeguideJson(Station* st, const Request& req, const RouteMatch& m, Reply reply) {
  sizeGuide(st, false, req, m, std::move(reply));
}

// GET /api/items/{id}/sizeguide.csv
void getItemsByIdSizeguideCsv(Station* st, const Request& req, const RouteMatch& m, Reply reply) {
  sizeGuide(st, true, req, m, std::move(reply));
}

// GET /api/items/{id}/result.json
void getItemsByIdResultJson(Station* st, const Request&, const RouteMatch& m, Reply reply) {
  const auto id = m.id("id");
  st->withCatalog(
      [reply, id](Catalog& c) {
        auto r = c.result(id);
        reply(r ? jsonResponse(http::status::ok, *r)
                : jsonError(http::status::not_found, "no result for item " + std::to_string(id)));
      },
      reply);
}

// GET /api/calibration
void getCalibration(Station* st, const Request&, const RouteMatch&, Reply reply) {
  st->withCatalog(
      [reply](Catalog& c) {
        auto cal = c.latestCalibration();
        if (!cal)
          return reply(jsonError(http::status::not_found, "the station is not calibrated"));
        reply(jsonResponse(http::status::ok, {{"id", cal->id},
                                              {"created_at", cal->createdAt},
                                              {"empty_sha256", cal->emptySha256},
                                              {"calibration", cal->json}}));
      },
      reply);
}

// POST /api/sim/camera
void postSimCamera(Station* st, const Request& req, const RouteMatch&, Reply reply) {
  const auto body = parseJsonBody(req);
  const char* kShape = R"(body must be {"present": true|false, "still_delay_ms": 0..120000})";
  if (!body.is_object() || body.empty())
    throw BadRequest(kShape);
  for (const auto& [key, value] : body.items()) {
    if (key == "present" && !value.is_boolean())
      throw BadRequest(kShape);
    if (key == "still_delay_ms" && (!value.is_number_integer() || value.get<std::int64_t>() < 0 ||
                                    value.get<std::int64_t>() > 120000))
      throw BadRequest(kShape);
    if (key != "present" && key != "still_delay_ms")
      throw BadRequest("unknown field '" + key + "'; " + kShape);
  }
  if (!st->simulated())
    return reply(
        jsonError(http::status::forbidden, "only the simulated rig can fake camera faults"));
  nlohmann::json out = nlohmann::json::object();
  if (body.contains("still_delay_ms")) {
    st->setSimulatedStillDelay(std::chrono::milliseconds(body["still_delay_ms"].get<int>()));
    out["still_delay_ms"] = body["still_delay_ms"];
  }
  if (body.contains("present")) {
    st->setCameraUnplugged(!body["present"].get<bool>());
    out["present"] = body["present"];
  }
  reply(jsonResponse(http::status::ok, out));
}

#ifdef GARMCAP_TEST_HOOKS
// POST /api/sim/stall
void postSimStall(Station* st, const Request& req, const RouteMatch&, Reply reply) {
  const auto body = parseJsonBody(req);
  if (!body.is_object() || !body.contains("ms") || !body["ms"].is_number_integer() ||
      body["ms"].get<std::int64_t>() < 0 || body["ms"].get<std::int64_t>() > 30000)
    throw BadRequest(R"(body must be {"ms": 0..30000})");
  if (!st->simulated())
    return reply(jsonError(http::status::forbidden, "only the simulated rig can be stalled"));
  const int ms = body["ms"].get<int>();
  st->stallLoopForTest(std::chrono::milliseconds(ms), [reply, ms] {
    reply(jsonResponse(http::status::ok, {{"stalled_ms", ms}}));
  });
}
#endif

}  // namespace

void addApiRoutes(Router& router, Station& station) {
  using V = http::verb;
  Station* st = &station;

  router.add(V::get, "/api/status", withStation(st, getStatus));
  router.add(V::post, "/api/capture/empty", withStation(st, postCaptureEmpty));
  router.add(V::post, "/api/capture", withStation(st, postCapture));
  router.add(V::post, "/api/button", withStation(st, postButton));
  router.add(V::get, "/api/jobs/{id}", withStation(st, getJobsById));
  router.add(V::get, "/api/jobs", withStation(st, getJobs));
  router.addStream(V::get, "/api/events", withStation(st, getEvents));
  router.addStream(V::get, "/stream.mjpg", withStation(st, getStreamMjpg));
  router.add(V::get, "/api/items", withStation(st, getItems));
  router.add(V::get, "/api/items/{id}", withStation(st, getItemsById));
  router.add(V::patch, "/api/items/{id}", withStation(st, patchItemsById));
  router.add(V::delete_, "/api/items/{id}", withStation(st, deleteItemsById));
  router.add(V::post, "/api/items/{id}/restore", withStation(st, postItemsByIdRestore));
  router.add(V::post, "/api/items/{id}/rerun", withStation(st, postItemsByIdRerun));
  router.add(V::post, "/api/items/{id}/back", withStation(st, postItemsByIdBack));
  router.add(V::get, "/api/items/{id}/images/{kind}", withStation(st, getItemsByIdImagesByKind));
  router.add(V::get, "/api/items/{id}/pattern.json", withStation(st, getItemsByIdPatternJson));
  router.add(V::get, "/api/items/{id}/pattern.svg", withStation(st, getItemsByIdPatternSvg));
  router.add(V::get, "/api/items/{id}/sizeguide.json", withStation(st, getItemsByIdSizeguideJson));
  router.add(V::get, "/api/items/{id}/sizeguide.csv", withStation(st, getItemsByIdSizeguideCsv));
  router.add(V::get, "/api/items/{id}/result.json", withStation(st, getItemsByIdResultJson));
  router.add(V::get, "/api/calibration", withStation(st, getCalibration));

  // The simulated rig's camera faults: {"present": bool} unplugs or replugs it,
  // {"still_delay_ms": 0..120000} makes each still take that long (a hanging driver).
  router.add(V::post, "/api/sim/camera", withStation(st, postSimCamera));

#ifdef GARMCAP_TEST_HOOKS
  // Test builds only (CMake GARMCAP_TEST_HOOKS), and only on the simulated rig: blocks the event
  // loop, for the e2e test that the systemd watchdog pings stop while it is blocked.
  router.add(V::post, "/api/sim/stall", withStation(st, postSimStall));
#endif
}

}  // namespace garmcap::daemon
