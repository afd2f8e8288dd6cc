// Review routes for staff (issue 17): decide on many captures at once.
//
//   POST /api/items/review  {"ids": [3, 4, 9], "status": "approved" | "rejected" | "needs_review"}
//     -> 200 {"updated": [3, 4], "missing": [9]}
//
// Corrections of one item (type, attributes, measurements, title, price) go through
// PATCH /api/items/{id} (api_routes.cpp); the measured values stay in the item's result.json,
// so a corrected measurement keeps its original for the record.

#include <set>

#include "garmcap/daemon/catalog.h"
#include "garmcap/daemon/http_guard.h"
#include "garmcap/daemon/http_router.h"
#include "garmcap/daemon/station_routes.h"

namespace garmcap::daemon {
namespace {

constexpr std::size_t kMaxIds = 500;  // one page of the catalog grid, with room

struct ReviewRequest {
  std::vector<std::int64_t> ids;
  std::string status;
};

ReviewRequest parseReview(const nlohmann::json& body) {
  if (!body.is_object())
    throw BadRequest("body must be an object {\"ids\": [...], \"status\": ...}");
  for (const auto& [k, v] : body.items())
    if (k != "ids" && k != "status")
      throw BadRequest("unknown field '" + quoteInput(k) + "'");
  ReviewRequest r;
  if (!body.contains("status") || !body["status"].is_string())
    throw BadRequest("field 'status' must be approved, rejected or needs_review");
  r.status = body["status"].get<std::string>();
  if (r.status != kStatusApproved && r.status != kStatusRejected && r.status != kStatusNeedsReview)
    throw BadRequest("field 'status' must be approved, rejected or needs_review, got '" +
                     quoteInput(r.status) + "'");
  if (!body.contains("ids") || !body["ids"].is_array() || body["ids"].empty() ||
      body["ids"].size() > kMaxIds)
    throw BadRequest("field 'ids' must be an array of 1.." + std::to_string(kMaxIds) + " item ids");
  std::set<std::int64_t> seen;
  for (const auto& v : body["ids"]) {
    if (!v.is_number_integer() || v.get<std::int64_t>() <= 0)
      throw BadRequest("field 'ids' must hold positive integers");
    if (seen.insert(v.get<std::int64_t>()).second)
      r.ids.push_back(v.get<std::int64_t>());
  }
  return r;
}

}  // namespace

void addReviewRoutes(Router& router, RouteContext& ctx) {
  RouteContext* c = &ctx;
  router.add(
      http::verb::post, "/api/items/review",
      [c](const Request& req, const RouteMatch&, Reply reply) {
        const ReviewRequest r = parseReview(parseJsonBody(req));
        c->withCatalog(
            [reply, r](Catalog& cat) {
              nlohmann::json updated = nlohmann::json::array();
              nlohmann::json missing = nlohmann::json::array();
              ItemPatch patch;
              patch.status = r.status;
              try {
                for (const auto id : r.ids)
                  (cat.patchItem(id, patch) ? updated : missing).push_back(id);
              } catch (const CatalogError& e) {
                return reply(jsonError(http::status::bad_request, e.what()));
              }
              reply(jsonResponse(http::status::ok, {{"updated", updated}, {"missing", missing}}));
            },
            reply);
      });
}

}  // namespace garmcap::daemon
