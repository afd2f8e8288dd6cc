#pragma once
// Sends the station's catalog to the chain's hub (docs/hub.md) and applies the hub's edits.
//
// One thread of its own. It reads the outbox (catalog.h) in sequence order; for each row it
// sends the blobs of the item that the hub lacks (HEAD, then PUT), then the item's current state
// (POST /api/hub/push, idempotent at the hub by station and local id), and removes the row only
// after the hub's 2xx. A failure (hub down, network, a 5xx or 4xx) waits 0.5 s, doubling up to
// 30 s, then the same row is tried again: the outbox is durable, so a restart resumes where the
// last run stopped, and a row sent twice is the same upsert twice. Between rows it pulls the
// hub's edits (GET /api/hub/changes?since=cursor) and applies them with Catalog::applyHubEdit,
// which queues nothing, so an edit from the hub never comes back as a push.
//
// The catalog is reached only through RouteContext::withCatalog (the station strand owns it);
// blobs are read from the content store, which is thread-safe.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

#include "garmcap/daemon/config.h"
#include "garmcap/daemon/http_router.h"

namespace garmcap::daemon {

/// The retry delay after `failures` failures in a row: 0.5 s doubling, at most 30 s.
std::chrono::milliseconds hubBackoff(int failures);

class HubPusher {
 public:
  /// `config.hubUrl` must be valid (Config::validate). Does not start the thread.
  HubPusher(RouteContext& station, const Config& config);
  ~HubPusher();
  HubPusher(const HubPusher&) = delete;
  HubPusher& operator=(const HubPusher&) = delete;

  void start();
  /// Stops the thread (at most one HTTP timeout, 5 s, later).
  void stop();

  struct Counters {
    std::atomic<std::int64_t> pushed{0}, blobsSent{0}, changesApplied{0}, failures{0};
  };
  const Counters& counters() const { return counters_; }

 private:
  void run();
  /// One pass: pushes up to a batch of outbox rows, then pulls the hub's changes. True when it
  /// did some work (the next pass follows at once).
  bool pass();

  RouteContext& station_;
  HubAddress hub_;
  std::string token_;
  std::chrono::milliseconds poll_;
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::atomic<bool> stopping_{false};
  Counters counters_;
};

}  // namespace garmcap::daemon
