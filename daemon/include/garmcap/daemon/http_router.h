#pragma once
// HTTP routing for garmcapd: plain handler functions, no socket knowledge (Beast 1.74 advanced
// server style: the session hands a parsed request to the router together with a `Reply`
// callback; the handler calls it exactly once, from any thread).
//
// ADDING A ROUTE (e.g. in daemon/src/export_routes.cpp):
//
//   #include "garmcap/daemon/station_routes.h"   // declares addExportRoutes
//   namespace garmcap::daemon {
//   void addExportRoutes(Router& router, RouteContext& ctx) {
//     router.add(http::verb::get, "/api/items/{id}/pattern.{ext}",
//                [&ctx](const Request& req, const RouteMatch& m, Reply reply) {
//                  const std::int64_t id = m.id("id");   // validated positive integer or 400
//                  ctx.withCatalog([id, reply](Catalog& catalog) {   // runs on the state strand
//                    auto item = catalog.item(id);
//                    if (!item) return reply(jsonError(http::status::not_found, "no item 7"));
//                    reply(textResponse(http::status::ok, "text/plain", "..."));
//                  });
//                });
//   }
//   }  // namespace garmcap::daemon
//
// and call it from addStationRoutes (station_routes.cpp), which garmcapd runs before it serves.
//
// Patterns: a segment is literal, or `{name}` with an optional literal prefix/suffix inside the
// segment (`pattern.{ext}`, `{id}.json`). A captured value is 1..64 characters of
// [A-Za-z0-9_-] only: no dot, no slash, no percent sign, so `..` can never reach a handler.
// Routes are matched in the order they were added; the first full match wins. A path that
// matches a pattern with another verb answers 405. Query parameters are percent-decoded into
// RouteMatch::query (raw values, validate them yourself).
//
// Heavy work (PDF, DXF, image encoding) goes to `ctx.offload`, catalog access to
// `ctx.withCatalog` (the catalog connection is owned by one strand; never keep the Catalog&
// beyond the callback). Handlers must not throw; an exception escaping one becomes a 500 with
// its message, logged once.
//
// STATIC FILES: the web UI lives in daemon/web/ (owned by the web UI). CMake copies it to
// <build>/share/garmcap/web and garmcapd serves it from the directory compiled in as
// GARMCAP_WEB_DIR (override: config `[http] web_dir` or `--web-dir`). At start-up (and on
// SIGHUP) StaticFiles scans that directory once and builds a whitelist of regular files whose
// relative path is made of [A-Za-z0-9._-] segments not starting with '.'; a request is served
// only if its path is a key of that whitelist, so no request text is ever joined to a path.
// `/` serves index.html. Content types come from the extension (html, js, mjs, css, svg, png,
// jpg, jpeg, webp, ico, json, txt, woff2, map); other extensions are not whitelisted.

#include <boost/beast/http.hpp>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "garmcap/daemon/config.h"

namespace garmcap::daemon {

namespace http = boost::beast::http;

using Request = http::request<http::string_body>;
using Response = http::response<http::string_body>;
/// Sends the response. Call exactly once; safe from any thread (it posts to the session).
using Reply = std::function<void(Response)>;

class Catalog;
class ContentStore;

/// Thrown by RouteMatch accessors and helpers for a bad request; the router answers 400 with
/// the message.
class BadRequest : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct RouteMatch {
  std::map<std::string, std::string> params;  // from `{name}` segments, charset-checked
  std::map<std::string, std::string> query;   // percent-decoded, valid UTF-8
  // Query names whose value was not valid percent-encoded UTF-8, and why: queryValue() refuses
  // them by name, so one bad byte is a 400 for that parameter, never a crash or a silent drop.
  std::map<std::string, std::string> badQuery;

  /// The parameter as a positive 63-bit integer id; throws BadRequest naming it otherwise.
  std::int64_t id(const std::string& name) const;
  const std::string& param(const std::string& name) const;
  /// The decoded value; throws BadRequest naming the parameter when it was malformed.
  std::optional<std::string> queryValue(const std::string& name) const;
};

using Handler = std::function<void(const Request&, const RouteMatch&, Reply)>;

/// A long-lived response (server-sent events, MJPEG). The handler writes the header once, then
/// chunks; writes are queued (bounded: the oldest unsent chunk is dropped when `maxQueued` is
/// reached, so a slow client never blocks the station). `open()` turns false once the peer went
/// away; keep a shared_ptr only while you stream.
class StreamSink {
 public:
  virtual ~StreamSink() = default;
  virtual void writeHeader(Response header) = 0;  // body ignored; sent with no Content-Length
  virtual void write(std::string chunk) = 0;
  virtual bool open() const = 0;
  virtual void close() = 0;
};
using StreamHandler =
    std::function<void(const Request&, const RouteMatch&, std::shared_ptr<StreamSink>)>;

class Router {
 public:
  void add(http::verb verb, std::string pattern, Handler handler);
  void addStream(http::verb verb, std::string pattern, StreamHandler handler);

  struct Match {
    const Handler* handler = nullptr;
    const StreamHandler* stream = nullptr;
    RouteMatch match;
    bool pathMatched = false;  // some route matched the path but not the verb -> 405
  };
  /// Finds the route for a request target (path + optional query). Never throws on bad input:
  /// a target that cannot match (bad charset, too long, `..`) gives an empty Match.
  Match find(http::verb verb, std::string_view target) const;

  /// Dispatches a non-stream request: 404/405/400/500 answered here. Used by the session and by
  /// unit tests (no socket needed).
  void dispatch(const Request& request, Reply reply) const;

  struct Route;  // compiled pattern (http_router.cpp)

 private:
  std::vector<std::shared_ptr<Route>> routes_;
};

/// What route functions get: serialized catalog access, a worker pool and the stores.
class RouteContext {
 public:
  virtual ~RouteContext() = default;
  /// Runs `fn` on the strand that owns the catalog. An exception thrown by `fn` is logged and
  /// answered on `failed` (BadRequest as 400, anything else as a 500 without its text: SQL and
  /// paths stay in the log), so the client is never left without an answer.
  virtual void withCatalog(std::function<void(Catalog&)> fn, Reply failed) = 0;
  /// Runs `fn` on the worker pool (OpenCV, PDF, zip work); exceptions as for withCatalog.
  virtual void offload(std::function<void()> fn, Reply failed) = 0;
  /// The content-addressed image store (thread-safe, read-only use from handlers).
  virtual const ContentStore& store() const = 0;
  /// The file-naming template from the config, e.g. "{sku}_{kind}" (see naming.h).
  virtual std::string namingTemplate() const = 0;
  /// Pieces one marker may lay (the config's [marker] max_pieces); more is a 422 naming it.
  virtual int markerMaxPieces() const = 0;
  /// The shop settings in force (brand, links, size labels): the config's [shop] section with
  /// what the shop saved from the setup screen over it, a copy.
  virtual ShopConfig shopConfig() const = 0;
  /// The settings saved from the setup screen (a JSON object of [shop] keys, maybe empty).
  virtual nlohmann::json savedShopSettings() const = 0;
  /// Call inside withCatalog: checks `changes` (a JSON object of [shop] keys) as the config's
  /// [shop] section is checked, stores them over the saved ones and returns the settings now in
  /// force. Throws BadRequest naming the key for a bad one; nothing is stored then.
  virtual ShopConfig saveShopSettings(Catalog& catalog, const nlohmann::json& changes) = 0;
};

// --- Response helpers -----------------------------------------------------------------------
Response jsonResponse(http::status status, const nlohmann::json& body);
/// `{"error": message}` with the status.
Response jsonError(http::status status, const std::string& message);

/// Answers `failed` for an exception a deferred handler threw (withCatalog, offload): 400 for
/// BadRequest, else a 500 whose details go only to the log under `what`.
void replyFailure(const Reply& failed, const std::string& what, std::exception_ptr error);
Response textResponse(http::status status, std::string contentType, std::string body);
/// Parses a JSON request body; throws BadRequest ("malformed JSON body: ...") otherwise.
nlohmann::json parseJsonBody(const Request& request);

/// Serves the whitelisted files of the web directory (see STATIC FILES above).
class StaticFiles {
 public:
  explicit StaticFiles(std::string webDir);
  /// Rescans the directory (start-up and SIGHUP).
  void rescan();
  /// Response for a request path ("/", "/app.js", "/img/logo.svg"); nullopt when not listed.
  std::optional<Response> serve(std::string_view path, unsigned version, bool keepAlive) const;
  std::size_t fileCount() const { return files_.size(); }
  static std::optional<std::string> contentType(std::string_view fileName);

 private:
  std::string dir_;
  std::map<std::string, std::pair<std::string, std::string>> files_;  // url -> (fs path, type)
};

}  // namespace garmcap::daemon
