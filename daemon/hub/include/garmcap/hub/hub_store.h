#pragma once
// The hub's catalog on PostgreSQL (libpqxx 6.4): items of several stations, each keyed by
// (station, station-local id), their measurements, patterns (schema 2), and the images
// content-addressed by sha256 in a bytea column. Schema versions are rows of schema_migrations,
// applied in order, each in its own transaction under an advisory lock (two hubs starting on one
// database do not race).
//
// Ownership (docs/hub.md): the station owns every field of an item until the item is approved;
// from then on the hub owns title, price and status. A push of an approved item keeps the hub's
// values of those three, and when the station sent other values a change is queued for that
// station so that it comes round to the hub's (GET /api/hub/changes).
//
// Thread-safe: a small pool of connections, one per call in flight; a connection that broke
// (the server restarted) is replaced on the next call. Errors: HubStoreError for what the
// caller did wrong (unknown blob, bad status), pqxx exceptions for the database.

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace garmcap::hub {

class HubStoreError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline constexpr int kHubSchemaVersion = 3;

/// One image of a pushed item: the blob must be at the hub already.
struct PushedImage {
  std::string kind, sha256, mediaType;
};

/// What a station sends for one item (POST /api/hub/push).
struct PushedItem {
  std::int64_t localId = 0;
  std::string sku, title, status, type;
  std::optional<std::int64_t> priceCents;
  std::map<std::string, double> measurementsCm;
  std::vector<PushedImage> images;
  bool deleted = false;
  nlohmann::json doc;  // the station's whole item JSON, kept for reading and exports
  // The item's patterns (size -> the drafts library's pattern JSON, "base" = as measured);
  // none: the push left them out (a station from before patterns were sent), kept as they are.
  std::optional<std::map<std::string, nlohmann::json>> patterns;
};

struct PushOutcome {
  std::int64_t hubId = 0;
  bool created = false;
  bool hubKept = false;  // the hub owns title/price/status and kept its values
};

struct HubItem {
  std::int64_t id = 0;
  std::string station;
  std::int64_t localId = 0;
  std::string sku, title, status, type;
  std::optional<std::int64_t> priceCents;
  bool hubOwned = false;
  std::map<std::string, double> measurementsCm;
  std::vector<PushedImage> images;
  nlohmann::json doc;
  std::vector<std::string> patternSizes;           // item(id) only
  std::map<std::string, nlohmann::json> patterns;  // approvedItems(..., true) only
  std::string createdAt, updatedAt;
  std::optional<std::string> deletedAt;
  nlohmann::json toJson() const;
};

struct HubQuery {
  std::string station;       // "" = every station
  std::string search;        // substring of sku or title, case-insensitive; "" = any
  std::string status;        // needs_review, approved or rejected; "" = any
  std::int64_t afterId = 0;  // keyset: items with a smaller id than this (newest first); 0 = start
  int limit = 50;            // 1..500
};

struct HubPage {
  std::vector<HubItem> items;
  std::optional<std::int64_t> next;  // pass as afterId for the next page
};

/// A station the hub knows (configured now or before) and its items that are not deleted.
struct HubStation {
  std::string id;
  std::int64_t items = 0;  // not deleted
  // Of those, by status (needs_review, approved, rejected; a status with none is absent): the
  // export page says how many items a shop file holds (the approved) and how many it leaves out.
  std::map<std::string, std::int64_t> byStatus;
};

/// What PATCH /api/items/<id> may set at the hub.
struct HubPatch {
  std::optional<std::string> title, status;
  std::optional<std::optional<std::int64_t>> priceCents;
};

enum class PatchResult { kOk, kNotFound, kStationOwned };

/// An edit made at the hub, for its station to apply.
struct HubChange {
  std::int64_t seq = 0;
  std::int64_t localId = 0;
  std::string title, status;
  std::optional<std::int64_t> priceCents;
  nlohmann::json toJson() const;
};

/// The approved items that are not deleted, of a station or of all, oldest first, read in
/// keyset pages from one snapshot: a repeatable-read transaction on a connection of its own
/// (outside the pool), for an export written as it is read. rewind() starts again on the same
/// snapshot.
class ApprovedReader {
 public:
  virtual ~ApprovedReader() = default;
  /// The next page (with measurements and images); empty at the end.
  virtual std::vector<HubItem> next(int limit) = 0;
  virtual void rewind() = 0;
  /// An item's stored patterns (size -> pattern JSON) and a blob's bytes, in the same snapshot:
  /// catalog.zip reads them one item at a time.
  virtual std::map<std::string, nlohmann::json> patterns(std::int64_t itemId) = 0;
  virtual std::optional<std::string> blob(const std::string& sha256) = 0;
};

class HubStore {
 public:
  /// Connects (libpq connection string) and migrates. Throws pqxx or HubStoreError.
  explicit HubStore(std::string connectionString, int connections = 4);
  ~HubStore();
  HubStore(const HubStore&) = delete;
  HubStore& operator=(const HubStore&) = delete;

  int schemaVersion();

  /// Makes the configured stations known (token hashes replaced); stations not listed stay
  /// (their items remain) but can no longer authenticate.
  void setStations(const std::map<std::string, std::string>& tokenSha256ByStation);
  /// The station whose token hash this is, if any. A lookup by hash: timing tells an attacker
  /// about hashes of his guesses, nothing about a token.
  std::optional<std::string> stationForToken(const std::string& tokenSha256);
  /// Every station of the stations table, by name.
  std::vector<HubStation> stations();

  bool hasBlob(const std::string& sha256);
  /// Stores bytes under their sha256 (the caller checked it). Idempotent.
  void putBlob(const std::string& sha256, const std::string& bytes);
  std::optional<std::string> blob(const std::string& sha256);
  /// True when an item of `station` shows this blob (what a station token may download).
  bool blobOfStation(const std::string& sha256, const std::string& station);

  /// Idempotent upsert by (station, local id). Throws HubStoreError naming a missing blob or a
  /// bad field.
  PushOutcome push(const std::string& station, const PushedItem& item);

  std::optional<HubItem> item(std::int64_t id);
  HubPage list(const HubQuery& query);
  /// The approved items that are not deleted, of `station` ("" = every station), oldest first,
  /// with their measurements and images: what the chain's shop exports take. One snapshot.
  /// With `withPatterns`, each item's patterns too (catalog.zip); at most `limit` items.
  std::vector<HubItem> approvedItems(const std::string& station, bool withPatterns = false,
                                     std::size_t limit = std::numeric_limits<std::size_t>::max());
  /// approvedItems page by page: `station` "" = every station.
  std::unique_ptr<ApprovedReader> readApproved(const std::string& station);
  /// An item's stored pattern of `size`, if any.
  std::optional<nlohmann::json> pattern(std::int64_t itemId, const std::string& size);
  /// An item's stored patterns, size -> pattern JSON.
  std::map<std::string, nlohmann::json> patterns(std::int64_t itemId);
  PatchResult patch(std::int64_t id, const HubPatch& patch);
  /// Changes for `station` after `since`, oldest first.
  std::vector<HubChange> changes(const std::string& station, std::int64_t since, int limit);
  /// Every item of a station, for tests and the exports: (local id -> hub id).
  std::map<std::int64_t, std::int64_t> stationItems(const std::string& station);

 private:
  struct Connection;  // a pqxx::connection (hub_store.cpp)
  std::unique_ptr<Connection> acquire();
  void release(std::unique_ptr<Connection> c, bool healthy);
  void migrate();
  /// Runs `fn(pqxx::connection&)` on a pooled connection; once more on a fresh connection when
  /// the first one turns out broken (the server restarted since it was opened).
  template <typename Fn>
  auto withConnection(Fn&& fn);

  std::string connectionString_;
  std::mutex mutex_;
  std::condition_variable available_;
  std::vector<std::unique_ptr<Connection>> idle_;
  int capacity_ = 0;
  int open_ = 0;
  std::mutex tokensMutex_;
  std::map<std::string, std::string> stationByToken_;  // token sha256 -> station
};

}  // namespace garmcap::hub
