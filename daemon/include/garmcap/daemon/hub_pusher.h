#pragma once
// Sends the station's catalog to the chain's hub (docs/hub.md) and applies the hub's edits.
//
// One thread of its own. It reads the outbox (catalog.h) in sequence order; for each row it
// sends the blobs of the item that the hub lacks (HEAD, then PUT), then the item's current state
// (POST /api/hub/push, idempotent at the hub by station and local id), and removes the row only
// after the hub's 2xx. A 4xx that a retry cannot change (hubRefusesForGood) parks the row in
// the catalog's refused rows with the hub's answer, and the next row goes; a 401/403 (a wrong
// token) parks nothing and waits 30 s between tries, reported in status(). Any other failure
// (hub down, network, a 5xx, 408, 429) waits 0.5 s, doubling up to 30 s, then the same row is
// tried again. Over https:// the hub's certificate is verified against [hub] ca_file (or the
// system's store) and must name the host of [hub] url; a failed verification is such a failure
// too, retried with the backoff and reported in status() ("tls_error"). The outbox is durable, so a
// restart resumes where the last run stopped, and a row sent twice is the same upsert twice.
// Between rows it pulls the hub's edits (GET /api/hub/changes?since=cursor) and applies them with
// Catalog::applyHubEdit, which queues nothing, so an edit from the hub never comes back as a push.
//
// The catalog is reached only through RouteContext::withCatalog (the station strand owns it);
// blobs are read from the content store, which is thread-safe.

#include <atomic>
#include <boost/asio/ssl/context.hpp>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>

#include "garmcap/daemon/catalog.h"
#include "garmcap/daemon/config.h"
#include "garmcap/daemon/http_router.h"

namespace garmcap::daemon {

/// The retry delay after `failures` failures in a row: 0.5 s doubling, at most 30 s.
std::chrono::milliseconds hubBackoff(int failures);
/// A hub answer that no retry will change (400, 404, 409, 413, 422): the row is parked.
bool hubRefusesForGood(int status);
/// The hub refused the token (401, 403): nothing is parked, the pusher waits and reports it.
bool hubRefusesToken(int status);

class HubPusher {
 public:
  /// `config.hubUrl` must be valid (Config::validate). Does not start the thread.
  HubPusher(RouteContext& station, const Config& config);
  ~HubPusher();
  HubPusher(const HubPusher&) = delete;
  HubPusher& operator=(const HubPusher&) = delete;

  void start();
  /// Stops the thread (at most one step of an HTTP call, 5 s, later).
  void stop();

  struct Counters {
    std::atomic<std::int64_t> pushed{0}, blobsSent{0}, changesApplied{0}, failures{0}, refused{0};
  };
  const Counters& counters() const { return counters_; }
  /// The hub's refusal of the token from the last try, empty while the token is taken.
  std::string tokenRefused() const;
  /// Why the last TLS handshake with the hub failed (its certificate, its name), empty once a
  /// pass succeeds.
  std::string tlsFailed() const;
  /// For the station's /api/status (thread-safe): the counters and a refused token.
  nlohmann::json status() const;

 private:
  void run();
  /// One pass: pushes up to a batch of outbox rows, then pulls the hub's changes. True when it
  /// did some work (the next pass follows at once).
  bool pass();
  void park(const OutboxEntry& row, const std::pair<int, std::string>& refusal);

  RouteContext& station_;
  HubAddress hub_;
  std::shared_ptr<boost::asio::ssl::context> tls_;  // for https:// only
  std::string token_;
  std::chrono::milliseconds poll_;
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::atomic<bool> stopping_{false};
  Counters counters_;
  mutable std::mutex statusMutex_;
  std::string tokenRefused_;
  std::string tlsFailed_;
};

}  // namespace garmcap::daemon
