#include "garmcap/hub/hub_exports.h"

#include <spdlog/spdlog.h>

#include <atomic>
#include <functional>
#include <map>
#include <set>

#include "garmcap/daemon/download_sink.h"
#include "garmcap/daemon/export_items.h"
#include "garmcap/daemon/export_shop.h"
#include "garmcap/daemon/utf8.h"
#include "garmcap/hub/hub_caller.h"
#include "garmcap/hub/hub_catalog_zip.h"

namespace garmcap::hub {

namespace http = daemon::http;
using daemon::BadRequest;
using daemon::jsonError;
using daemon::Reply;
using daemon::Request;
using daemon::Response;
using daemon::RouteMatch;

namespace {

std::string docString(const nlohmann::json& doc, const char* key) {
  return doc.contains(key) && doc[key].is_string() ? doc[key].get<std::string>() : "";
}

using ShopBuild = std::function<daemon::ShopFile(const std::vector<daemon::ExportItem>&,
                                                 const daemon::ShopOptions&)>;

const char* kReadsWhat =
    "a station token exports only its own station's items; the admin token every station's";

// Exports being written at once (each holds a database connection for its snapshot).
constexpr int kMaxStreamingExports = 2;
// Items read, built and sent at a time: what the hub holds of an export.
constexpr int kExportPageItems = 500;
// The warnings' text the headers carry (setExportWarnings keeps 2,000 characters).
constexpr std::size_t kWarningTextKept = 2000;

// A response that is not a download (401, 403, 400, 422, 503) on a stream route.
void answer(daemon::StreamSink& sink, Response r) {
  r.prepare_payload();
  std::string body = std::move(r.body());
  r.body().clear();
  r.set(http::field::content_length, std::to_string(body.size()));
  sink.writeHeader(std::move(r));
  sink.write(std::move(body));
  sink.close();
}

}  // namespace

// One of the chain's shop files written as it is read (docs/hub.md, "Shop exports for the
// chain"): pass 1 (survey) builds every page and keeps only what the header needs, the warnings
// and WooCommerce's measurement columns; pass 2 reads the same snapshot again and sends each
// page as an HTTP/1.1 chunk, the next page only once the previous one is on the wire. The hub
// holds one page (kExportPageItems) of a file, not the file.
class ChainShopStream : public std::enable_shared_from_this<ChainShopStream> {
 public:
  // `columns` set: the file's measurement columns (pass 2); `survey` set: add this page's.
  using Build = std::function<daemon::ShopFile(
      const std::vector<daemon::ExportItem>&, const daemon::ShopOptions&,
      const std::set<std::string>* columns, std::set<std::string>* survey)>;

  ChainShopStream(std::unique_ptr<ApprovedReader> reader, daemon::ShopOptions options, Build build,
                  std::shared_ptr<daemon::StreamSink> sink, daemon::DownloadSink& download,
                  std::shared_ptr<void> slot)
      : reader_(std::move(reader)),
        options_(std::move(options)),
        build_(std::move(build)),
        sink_(std::move(sink)),
        download_(download),
        slot_(std::move(slot)) {}

  /// Pass 1: the 200 header with the export's warnings. Throws ExportError (the caller's 422).
  Response survey() {
    std::size_t total = 0, textSize = 0;
    std::vector<std::string> kept;
    bool any = false;
    for (;;) {
      const auto page = reader_->next(kExportPageItems);
      if (page.empty() && any)
        break;
      any = true;
      std::vector<std::string> warnings;
      const auto items = shopPage(page, warnings);
      daemon::ShopFile f = build_(items, options_, nullptr, &columns_);
      warnings.insert(warnings.end(), f.warnings.begin(), f.warnings.end());
      total += warnings.size();
      for (auto& w : warnings)
        if (textSize < kWarningTextKept) {
          textSize += w.size() + 3;
          kept.push_back(std::move(w));
        }
      if (page.empty())
        break;
    }
    reader_->rewind();
    Response head{http::status::ok, 11};
    daemon::setExportWarnings(head, kept);
    head.set("X-Export-Warnings", std::to_string(total));
    return head;
  }

  /// Pass 2: the next page as a chunk, then (once it is sent) the one after; the last chunk
  /// ends the body. A failure half-way closes the connection without the last chunk, so the
  /// client sees a truncated download, never a short file that looks whole.
  void next() {
    if (!sink_->open())
      return;
    try {
      std::string piece;
      while (piece.empty()) {
        const auto page = reader_->next(kExportPageItems);
        if (page.empty() && !first_) {
          download_.writeThen("0\r\n\r\n", [sink = sink_] { sink->close(); });
          return;
        }
        std::vector<std::string> warnings;
        daemon::ShopFile f = build_(shopPage(page, warnings), options_, &columns_, nullptr);
        piece = withoutRepeatedHeader(std::move(f.bytes));
        if (page.empty())
          break;  // an empty export: its header only
      }
      download_.writeThen(daemon::httpChunk(piece), [self = shared_from_this()] { self->next(); });
    } catch (const std::exception& e) {
      spdlog::error("hub: an export failed half-way, the download is cut short: {}", e.what());
      sink_->close();
    }
  }

 private:
  std::vector<daemon::ExportItem> shopPage(const std::vector<HubItem>& page,
                                           std::vector<std::string>& warnings) const {
    std::vector<daemon::Item> items;
    std::vector<std::optional<nlohmann::json>> guides;
    std::map<std::int64_t, std::string> labels;  // hub id -> "item 12 (shop1 #7)"
    for (const auto& h : page) {
      items.push_back(catalogItemOf(h));
      guides.push_back(sizeGuideOf(h));
      labels[h.id] = "item " + std::to_string(h.id) + " (" + h.station + " #" +
                     std::to_string(h.localId) + ")";
    }
    return daemon::shopItems(items, guides, warnings,
                             [&](const daemon::Item& it) { return labels.at(it.id); });
  }

  // Every page is a whole file; the first keeps its header line, the others lose theirs, which
  // must be the same line (the columns are fixed by pass 1).
  std::string withoutRepeatedHeader(std::string bytes) {
    const auto end = bytes.find('\n');
    const std::string header = bytes.substr(0, end == std::string::npos ? bytes.size() : end + 1);
    if (first_) {
      first_ = false;
      header_ = header;
      return bytes;
    }
    if (header != header_)
      throw std::logic_error("a page of the export has other columns than the first");
    return bytes.substr(header.size());
  }

  std::unique_ptr<ApprovedReader> reader_;
  daemon::ShopOptions options_;
  Build build_;
  std::shared_ptr<daemon::StreamSink> sink_;
  daemon::DownloadSink& download_;
  std::shared_ptr<void> slot_;
  std::set<std::string> columns_;
  bool first_ = true;
  std::string header_;
};

daemon::Item catalogItemOf(const HubItem& h) {
  daemon::Item it;
  it.id = h.id;
  it.sku = h.sku;
  it.title = h.title;
  it.priceCents = h.priceCents;
  it.status = h.status;
  it.type = h.type;
  it.notes = docString(h.doc, "notes");
  it.baseSize = docString(h.doc, "base_size");
  if (h.doc.contains("tags") && h.doc["tags"].is_array())
    for (const auto& t : h.doc["tags"])
      if (t.is_string())
        it.tags.push_back(t.get<std::string>());
  if (h.doc.contains("attributes") && h.doc["attributes"].is_object())
    for (const auto& [k, v] : h.doc["attributes"].items())
      if (v.is_string())
        it.attributes[k] = v.get<std::string>();
  it.measurementsCm = h.measurementsCm;
  for (const auto& im : h.images)
    it.images.push_back({im.kind, im.sha256, im.mediaType, 0});
  it.createdAt = h.createdAt;
  it.updatedAt = h.updatedAt;
  it.deletedAt = h.deletedAt;
  return it;
}

std::optional<nlohmann::json> sizeGuideOf(const HubItem& h) {
  if (!h.doc.contains("size_guide") || h.doc["size_guide"].is_null())
    return std::nullopt;
  return h.doc["size_guide"];
}

void addHubExportRoutes(daemon::Router& router, HubStore& store, const HubConfig& config,
                        const HubLogins* logins) {
  auto running = std::make_shared<std::atomic<int>>(0);
  // What an export does once its caller, scope, options and slot are settled: send the header
  // and start the download, or throw (BadRequest, ExportError) before any byte of it.
  using Start = std::function<void(const std::string& scope, const daemon::ShopOptions&,
                                   std::shared_ptr<daemon::StreamSink>, daemon::DownloadSink&,
                                   std::shared_ptr<void> slot)>;
  auto exportRoute = [&store, &config, logins, running](std::string name, Start start) {
    return [&store, &config, logins, running, name, start](
               const Request& req, const RouteMatch& m, std::shared_ptr<daemon::StreamSink> sink) {
      try {
        const Caller c = callerOf(req, store, config, logins);
        if (!c.any())
          return answer(*sink, unauthorized("a station or admin token is required"));
        const auto scope = readScope(c, m);
        if (!scope)
          return answer(*sink, jsonError(http::status::forbidden, kReadsWhat));
        const daemon::ShopOptions options = daemon::shopOptions(m, config.shop);
        // Each export being written holds a database connection (its snapshot) until the
        // client has the whole file.
        if (running->fetch_add(1) >= kMaxStreamingExports) {
          running->fetch_sub(1);
          Response busy = jsonError(http::status::service_unavailable,
                                    "the hub is writing " + std::to_string(kMaxStreamingExports) +
                                        " exports already; retry in a minute");
          busy.set(http::field::retry_after, "60");
          return answer(*sink, std::move(busy));
        }
        auto slot = std::shared_ptr<void>(nullptr, [running](void*) { running->fetch_sub(1); });
        auto* download = dynamic_cast<daemon::DownloadSink*>(sink.get());
        if (!download)
          throw std::logic_error("the HTTP server's stream sink cannot carry a download");
        start(*scope, options, sink, *download, std::move(slot));
      } catch (const BadRequest& e) {
        answer(*sink, jsonError(http::status::bad_request, e.what()));
      } catch (const daemon::ExportError& e) {
        answer(*sink, jsonError(http::status::unprocessable_entity, e.what()));
      } catch (const std::exception& e) {
        spdlog::error("hub: export {} failed: {}", name, e.what());
        answer(*sink, jsonError(http::status::internal_server_error, e.what()));
      }
    };
  };
  auto shopRoute = [&store, exportRoute](std::string name, std::string type,
                                         ChainShopStream::Build build) {
    return exportRoute(name, [&store, name, type, build](
                                 const std::string& scope, const daemon::ShopOptions& options,
                                 std::shared_ptr<daemon::StreamSink> sink,
                                 daemon::DownloadSink& download, std::shared_ptr<void> slot) {
      auto stream = std::make_shared<ChainShopStream>(store.readApproved(scope), options, build,
                                                      sink, download, std::move(slot));
      Response head = stream->survey();
      head.set(http::field::content_disposition, "attachment; filename=\"" + name + "\"");
      head.set(http::field::cache_control, "no-store");
      head.set(http::field::content_type, type);
      head.set(http::field::transfer_encoding, "chunked");
      sink->writeHeader(std::move(head));
      stream->next();
    });
  };
  auto fixed = [](ShopBuild build) -> ChainShopStream::Build {
    return
        [build](const std::vector<daemon::ExportItem>& items, const daemon::ShopOptions& o,
                const std::set<std::string>*, std::set<std::string>*) { return build(items, o); };
  };
  router.addStream(http::verb::get, "/api/export/shopify.csv",
                   shopRoute("shopify.csv", "text/csv; charset=utf-8", fixed(daemon::shopifyCsv)));
  router.addStream(
      http::verb::get, "/api/export/woocommerce.csv",
      shopRoute("woocommerce.csv", "text/csv; charset=utf-8",
                [](const std::vector<daemon::ExportItem>& items, const daemon::ShopOptions& o,
                   const std::set<std::string>* columns, std::set<std::string>* survey) {
                  if (survey) {
                    const auto names = daemon::wooCommerceMetaNames(items, o);
                    survey->insert(names.begin(), names.end());
                  }
                  return columns ? daemon::wooCommerceCsvWithColumns(items, o, *columns)
                                 : daemon::wooCommerceCsv(items, o);
                }));
  router.addStream(http::verb::get, "/api/export/merchant.tsv",
                   shopRoute("merchant.tsv", "text/tab-separated-values; charset=utf-8",
                             fixed(daemon::merchantTsv)));
  // The station's catalog.zip over the approved items, written as it is read
  // (hub_catalog_zip.h); it shares the export slots with the shop files.
  router.addStream(
      http::verb::get, "/api/export/catalog.zip",
      exportRoute(
          "catalog.zip", [&store](const std::string& scope, const daemon::ShopOptions& options,
                                  std::shared_ptr<daemon::StreamSink> sink,
                                  daemon::DownloadSink& download, std::shared_ptr<void> slot) {
            streamChainCatalogZip(
                store.readApproved(scope), options,
                "GarmCap hub catalog export (" +
                    (scope.empty() ? std::string("every station") : "station " + scope) + ")",
                sink, download, std::move(slot));
          }));

  // The images the exports link to (daemon::exportImagePath, hub ids): "<id>-<kind>" names,
  // resolved through the hub's items, of approved items the caller may read.
  auto imageFile = [&store, &config, logins](std::string ext) {
    return [&store, &config, logins, ext](const Request& req, const RouteMatch& m, Reply reply) {
      const Caller c = callerOf(req, store, config, logins);
      if (!c.any())
        return reply(unauthorized("a station or admin token is required"));
      const std::string name = m.param("name");
      const auto dash = name.find('-');
      if (dash == std::string::npos || dash == 0)
        throw BadRequest("image name must be <item id>-<kind>, got '" + daemon::quoteInput(name) +
                         "'");
      RouteMatch idOnly;
      idOnly.params["id"] = name.substr(0, dash);
      const std::int64_t id = idOnly.id("id");
      const std::string kind = name.substr(dash + 1);
      const auto it = store.item(id);
      if (!it || it->deletedAt || it->status != "approved" ||
          (!c.admin && it->station != *c.station))
        return reply(jsonError(http::status::not_found, "no approved item " + std::to_string(id)));
      for (const auto& im : it->images)
        if (im.kind == kind && daemon::imageExtension(im.mediaType) == ext) {
          auto bytes = store.blob(im.sha256);
          if (!bytes)
            return reply(jsonError(http::status::internal_server_error,
                                   "image " + im.sha256 + " is missing from the hub"));
          Response r = daemon::textResponse(http::status::ok, im.mediaType, std::move(*bytes));
          r.set(http::field::cache_control, "public, max-age=86400");
          return reply(std::move(r));
        }
      reply(jsonError(http::status::not_found,
                      "item " + std::to_string(id) + " has no " + ext + " image '" + kind + "'"));
    };
  };
  router.add(http::verb::get, "/api/export/files/images/{name}.jpg", imageFile("jpg"));
  router.add(http::verb::get, "/api/export/files/images/{name}.png", imageFile("png"));
  router.add(http::verb::get, "/api/export/files/images/{name}.webp", imageFile("webp"));
}

}  // namespace garmcap::hub
