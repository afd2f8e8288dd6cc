#pragma once
// The hub's HTTP API (docs/hub.md) on the station's HTTP layer (router, request guard, Beast
// server): stations push items and blobs with their own token, read the hub's edits back; the
// admin token lists, reads and edits across stations.
//
//   POST  /api/hub/push               station: {"local_id", "item": {...}, "deleted"}
//   HEAD  /api/hub/blobs/<sha256>     station or admin: 200 if the hub has it, else 404
//   GET   /api/hub/blobs/<sha256>     station or admin: the bytes
//   PUT   /api/hub/blobs/<sha256>     station: the bytes; 400 unless their sha256 is the name
//   GET   /api/hub/changes?since=N    station: the hub's edits of its items after cursor N
//   GET   /api/items?station=&status=&q=&after=&limit=   admin or station: newest first, keyset
//   GET   /api/items/<id>             admin or station
//   PATCH /api/items/<id>             admin: {"title", "price_cents", "status"}
//   GET   /api/hub/health             anyone: {"ok": true, "schema": N}
//   GET   /api/session                anyone: who the caller is; POST/DELETE: hub_web_routes.h
//   GET   /api/export/shopify.csv ... the chain's shop files (hub_exports.h)

#include <boost/asio/io_context.hpp>
#include <memory>
#include <thread>
#include <vector>

#include "garmcap/daemon/http_router.h"
#include "garmcap/hub/hub_config.h"
#include "garmcap/hub/hub_store.h"
#include "garmcap/hub/hub_web_routes.h"

namespace garmcap::daemon {
class HttpServer;
class StaticFiles;
}  // namespace garmcap::daemon

namespace garmcap::hub {

/// Adds the routes above; `store`, `config` and `logins` outlive the router. With `logins`, a
/// browser session cookie (hub_web_routes.h) stands for the token that opened it.
void addHubRoutes(daemon::Router& router, HubStore& store, const HubConfig& config,
                  HubLogins* logins = nullptr);

/// A running hub: store, routes and server on `config.threads` threads.
class HubService {
 public:
  explicit HubService(const HubConfig& config);
  ~HubService();
  HubService(const HubService&) = delete;
  HubService& operator=(const HubService&) = delete;
  /// Binds and serves; throws naming the address.
  void start();
  void stop();
  std::uint16_t port() const;
  HubStore& store() { return *store_; }

 private:
  HubConfig config_;
  std::unique_ptr<HubStore> store_;
  HubLogins logins_;
  daemon::Router router_;
  std::unique_ptr<daemon::StaticFiles> files_;
  boost::asio::io_context io_;
  std::unique_ptr<daemon::HttpServer> server_;
  std::vector<std::thread> threads_;
};

}  // namespace garmcap::hub
