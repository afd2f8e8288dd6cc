#pragma once
// The station catalog: one SQLite file (WAL, synchronous=FULL, foreign keys), schema versioned by
// `PRAGMA user_version` with ordered migrations, identified by `PRAGMA application_id`, prepared
// statements only. Images are named by sha256 (ContentStore); the catalog stores names only.
//
// Thread: one Catalog per process, used only from the station strand (RouteContext::withCatalog).
// Errors: CatalogError (runtime_error) with the SQL step and SQLite's message; open() refuses a
// file of another application or a schema newer than this code.

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

struct sqlite3;

namespace garmcap::daemon {

class CatalogError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline constexpr std::int32_t kCatalogApplicationId = 0x47434150;  // "GCAP"
inline constexpr int kCatalogSchemaVersion = 6;

/// Review status of an item: a capture with low confidence or warnings starts as kNeedsReview and
/// cannot be exported until a person approves it.
inline constexpr const char* kStatusNeedsReview = "needs_review";
inline constexpr const char* kStatusApproved = "approved";
inline constexpr const char* kStatusRejected = "rejected";

struct ImageRef {
  std::string kind;       // "dressed", "empty", "cutout", "product", "product_4x5", "silhouette",
                          // "overlay", "texture"; "product_webp", "product_4x5_webp" (WebP)
  std::string sha256;     // ContentStore name
  std::string mediaType;  // "image/png", "image/jpeg", "image/webp"
  std::int64_t bytes = 0;
};

struct Item {
  std::int64_t id = 0;
  std::string sku;
  std::string title;
  std::optional<std::int64_t> priceCents;
  std::vector<std::string> tags;
  std::string notes;
  std::string status = kStatusNeedsReview;  // needs_review | approved | rejected
  std::string type;                         // top | dress | skirt | pants | "" (unknown)
  std::map<std::string, std::string> attributes;
  double confidence = 0;
  std::vector<std::string> warnings;
  std::map<std::string, double> measurementsCm;
  std::vector<ImageRef> images;
  std::vector<std::string> sizes;  // sizes with a stored pattern, base size first
  std::string baseSize;            // size the garment itself was measured as ("" if unknown)
  std::optional<std::int64_t> calibrationId;
  std::optional<std::int64_t> jobId;
  std::string createdAt;  // ISO 8601 UTC
  std::string updatedAt;
  std::optional<std::string> deletedAt;

  /// API representation (docs/api.md): id, sku, title, price, tags, notes, status, type,
  /// attributes, confidence, warnings, measurements (name -> cm), images (kind -> url), sizes...
  nlohmann::json toJson() const;
};

/// Everything a successful dressed capture adds, committed in one transaction.
struct NewItem {
  std::string sku;
  std::string title;
  std::string type;
  std::map<std::string, std::string> attributes;
  double confidence = 0;
  std::vector<std::string> warnings;
  std::map<std::string, double> measurementsCm;
  std::vector<ImageRef> images;  // blobs already durable in the store; rows added here
  std::map<std::string, nlohmann::json> patterns;  // size -> pattern JSON ("base" = as measured)
  std::string baseSize;
  nlohmann::json sizeGuide;  // dsw::sizeGuideJson (docs/formats.md) or null
  nlohmann::json result;     // the pipeline's result.json
  std::optional<std::int64_t> calibrationId;
  std::optional<std::int64_t> jobId;
  bool needsReview = true;
};

/// Fields a PATCH may change; unset members are left alone.
struct ItemPatch {
  std::optional<std::string> sku, title, notes, status, type;
  std::optional<std::optional<std::int64_t>> priceCents;  // set to nullopt to clear
  std::optional<std::vector<std::string>> tags;
  std::optional<std::map<std::string, std::string>> attributes;
  std::optional<std::map<std::string, double>> measurementsCm;  // replaces listed names only
};

/// What the hub may change on an item once it owns it (docs/hub.md, ownership rule).
struct HubEdit {
  std::optional<std::string> title, status;
  std::optional<std::optional<std::int64_t>> priceCents;  // set to nullopt to clear
};

/// Outbox kinds: the item's current state is to be sent, or the item was deleted.
inline constexpr const char* kOutboxUpsert = "item_upsert";
inline constexpr const char* kOutboxDelete = "item_delete";

/// One change waiting for the hub, in commit order (`seq` only grows).
struct OutboxEntry {
  std::int64_t seq = 0;
  std::string kind;  // kOutboxUpsert | kOutboxDelete
  std::int64_t itemId = 0;
  std::string createdAt;
};

/// An outbox row the hub refused for good (docs/hub.md): parked with the hub's answer.
struct RefusedOutboxEntry {
  OutboxEntry row;
  int httpStatus = 0;
  std::string reason;  // the hub's answer, shortened
  std::string refusedAt;
};

/// One taped measurement of an item (issue 15 part 7): what staff measured with a tape and what
/// the pipeline had read, uncorrected, when it was taped, under the item's type at that time.
struct TapeEntry {
  std::int64_t itemId = 0;
  std::string name;  // measurement name
  std::string type;  // top | dress | skirt | pants
  double tapeCm = 0;
  double measuredCm = 0;
  std::string createdAt;
};

struct ItemQuery {
  std::string search;    // substring of sku, title, notes or tags (case-insensitive)
  std::string type;      // exact type filter, "" = any
  std::string status;    // exact status filter, "" = any
  bool deleted = false;  // true: only deleted items (the bin), false: only live items
  int offset = 0;
  int limit = 50;  // 1..500
};

struct Calibration {
  std::int64_t id = 0;
  std::string createdAt;
  std::string emptySha256;  // the bare-form frame it was made from
  nlohmann::json json;      // calibration JSON (docs/formats.md)
};

struct Job {
  std::int64_t id = 0;
  std::string kind;   // "empty" | "dressed" | "rerun" | "back"
  std::string state;  // queued | running | done | failed
  std::string stage;
  double progress = 0;  // 0..1
  std::optional<std::int64_t> itemId;
  std::optional<std::int64_t> calibrationId;
  std::string error;
  std::string sku;            // typed SKU given with the request, if any
  std::string dressedSha256;  // stored frame (for re-runs; a back job's: its back shot)
  std::string emptySha256;
  std::string createdAt, updatedAt;

  nlohmann::json toJson()
      const;  // {"id", "kind", "state", "stage", "progress", "item_id", "error"}
};

class Catalog {
 public:
  /// How the catalog is opened: normally, or read-only when the disk is full (the station then
  /// serves what is stored; no write is attempted, each would fail as DiskFull).
  enum class Mode { kReadWrite, kReadOnly };
  /// Opens or creates the catalog, migrating older schemas (each step in a transaction). With
  /// kReadOnly the file must exist at the current schema; it is opened immutable (no lock, no
  /// -shm: a full disk has no room for one), so only this process may have written it, and a
  /// WAL left by a crash is not read (a clean stop checkpoints it).
  explicit Catalog(const std::filesystem::path& file, Mode mode = Mode::kReadWrite);
  bool readOnly() const { return readOnly_; }
  ~Catalog();
  Catalog(const Catalog&) = delete;
  Catalog& operator=(const Catalog&) = delete;

  int schemaVersion() const;
  /// "ok" or SQLite's list of problems.
  std::string integrityCheck();

  // --- images ------------------------------------------------------------------------------
  /// Records a durable blob (idempotent).
  void addImage(const std::string& sha256, const std::string& mediaType, std::int64_t bytes);
  std::optional<std::string> imageMediaType(const std::string& sha256);
  /// Every blob name a row refers to (for the start-up orphan sweep).
  std::set<std::string> referencedImages();
  /// Drops the image rows of blobs no row needs any more (no item, live or soft-deleted, no
  /// calibration, no job names them) among `candidates`, or among all images; one transaction.
  /// Returns the dropped names: the caller removes their files afterwards (a crash in between
  /// leaves unlisted files, which the start-up orphan sweep removes).
  std::vector<std::string> dropUnreferencedImages(
      std::optional<std::vector<std::string>> candidates = std::nullopt);
  /// Purges items soft-deleted before `cutoff`: their rows go (measurements, images, patterns and
  /// tape with them), their jobs stay without frames. With `keepUntilHubKnows`, an item whose
  /// change still waits in the outbox stays until the hub has it. Returns the blob names the
  /// purged rows held (candidates for dropUnreferencedImages).
  std::vector<std::string> purgeDeletedItems(std::chrono::system_clock::time_point cutoff,
                                             bool keepUntilHubKnows);
  /// Forgets the frames of jobs that failed before `cutoff` (kept until then for a look at what
  /// went wrong). Returns the blob names released.
  std::vector<std::string> forgetFailedJobFrames(std::chrono::system_clock::time_point cutoff);

  // --- calibrations --------------------------------------------------------------------------
  std::int64_t addCalibration(const std::string& emptySha256, const nlohmann::json& json);
  std::optional<Calibration> latestCalibration();
  std::optional<Calibration> calibration(std::int64_t id);

  // --- jobs ----------------------------------------------------------------------------------
  /// A queued job. `itemId` names the item a re-run works on (kept so that a queued re-run can
  /// be resumed after a restart); other kinds get theirs when they finish.
  std::int64_t addJob(const std::string& kind, const std::string& sku,
                      std::optional<std::int64_t> itemId = std::nullopt);
  std::optional<Job> job(std::int64_t id);
  void updateJob(std::int64_t id, const std::string& state, const std::string& stage,
                 double progress);
  void setJobFrames(std::int64_t id, const std::string& emptySha256,
                    const std::string& dressedSha256);
  void failJob(std::int64_t id, const std::string& error);
  void finishJob(std::int64_t id, std::optional<std::int64_t> itemId,
                 std::optional<std::int64_t> calibrationId);
  /// Marks running jobs failed ("<reason> (during <stage>)"); returns their ids. Start-up only:
  /// a job that was running when the process died is not retried (it may be what killed it).
  std::vector<std::int64_t> failInterruptedJobs(const std::string& reason);
  /// Marks queued jobs created more than `maxAge` ago failed with `reason`; returns their ids.
  /// Start-up only: the garment of an old press is likely gone from the form.
  std::vector<std::int64_t> expireQueuedJobs(std::chrono::seconds maxAge,
                                             const std::string& reason);
  /// Jobs still queued, oldest first (the station resumes them at start-up).
  std::vector<Job> queuedJobs();
  std::vector<Job> recentJobs(int limit);

  // --- settings ------------------------------------------------------------------------------
  /// A setting saved from the web UI ("shop": the setup screen's JSON), if any.
  std::optional<nlohmann::json> setting(const std::string& key);
  void setSetting(const std::string& key, const nlohmann::json& value);

  // --- tape measurements (issue 15 part 7) ----------------------------------------------------
  /// Adds or replaces the item's taped measurements (by name), one transaction. The caller has
  /// validated names, values and the item (api: recordTape).
  void setTape(std::int64_t itemId, const std::vector<TapeEntry>& entries);
  /// Taped measurements of live items (all, or one item's), by type, name, item.
  std::vector<TapeEntry> tapes(std::optional<std::int64_t> itemId = std::nullopt);
  /// Removes the item's taped measurements; returns how many there were.
  int deleteTape(std::int64_t itemId);

  // --- items ---------------------------------------------------------------------------------
  /// Inserts the item, measurements, images, patterns, size guide and finishes `jobId`, in one
  /// transaction. Returns the new id.
  std::int64_t addItem(const NewItem& item);
  /// Replaces the pipeline outputs of an existing item (re-run), one transaction. Returns the
  /// blob names of the images it replaced (candidates for dropUnreferencedImages).
  std::vector<std::string> replaceItemResults(std::int64_t id, const NewItem& results);
  /// Adds images to an existing live item without touching its results (the back shot), and
  /// finishes `jobId` (made with `calibrationId`) with it, releasing the job's frames (the item
  /// names the still now), one transaction: the item's images of
  /// the `replaces` kinds are unlinked first (a second back shot replaces the first one's, a kind
  /// it did not make is not left showing the old picture). Returns the blob names unlinked
  /// (candidates for dropUnreferencedImages). Throws CatalogError if there is no such live item.
  std::vector<std::string> addItemImages(std::int64_t id, const std::vector<std::string>& replaces,
                                         const std::vector<ImageRef>& images,
                                         std::optional<std::int64_t> jobId,
                                         std::optional<std::int64_t> calibrationId);
  std::optional<Item> item(std::int64_t id, bool includeDeleted = false);
  std::pair<std::vector<Item>, std::int64_t> items(const ItemQuery& query);  // page, total
  /// Throws CatalogError on a bad status value. Returns false if no such live item.
  bool patchItem(std::int64_t id, const ItemPatch& patch);
  bool deleteItem(std::int64_t id);  // soft delete (restorable)
  bool restoreItem(std::int64_t id);
  /// Applies what the hub changed (title, price, status) without queueing the item for the hub
  /// again (the hub has it already). Same checks as patchItem; false if no such live item.
  bool applyHubEdit(std::int64_t id, const HubEdit& edit);
  std::optional<nlohmann::json> pattern(std::int64_t itemId, const std::string& size);

  // --- outbox for the hub (docs/hub.md) -------------------------------------------------------
  // addItem, replaceItemResults, patchItem, deleteItem and restoreItem each add one row in their
  // own transaction; the pusher reads them in order and removes a row once the hub took it.
  std::vector<OutboxEntry> outbox(int limit = 100);  // oldest first
  bool removeOutbox(std::int64_t seq);
  std::int64_t outboxSize();
  /// Moves row `seq` from the outbox to the refused rows with the hub's status and reason, in
  /// one transaction; false if there is no such row.
  bool refuseOutbox(std::int64_t seq, int httpStatus, const std::string& reason);
  std::vector<RefusedOutboxEntry> refusedOutbox(int limit = 20);  // newest first
  std::int64_t refusedOutboxSize();
  /// The pusher's state (e.g. "changes_cursor"); nullopt when never set.
  std::optional<std::string> hubState(const std::string& key);
  void setHubState(const std::string& key, const std::string& value);
  std::optional<nlohmann::json> sizeGuide(std::int64_t itemId);
  std::optional<nlohmann::json> result(std::int64_t itemId);

  /// Low-level handle for tests and migrations.
  sqlite3* handle() { return db_; }

 private:
  class Statement;
  friend class Statement;
  void exec(const char* sql);
  void migrate();
  void checkReadable();
  void loadItemDetails(Item& item);
  void writeItemContents(std::int64_t id, const NewItem& n, const std::string& ts);
  bool patch(std::int64_t id, const ItemPatch& patch, bool queue);
  void queueForHub(const char* kind, std::int64_t itemId, const std::string& ts);
  std::string now() const;

  sqlite3* db_ = nullptr;
  std::filesystem::path file_;
  bool readOnly_ = false;
};

/// The schema of version `version` (1..4) as SQL, for fixtures in tests.
std::string catalogSchemaSql(int version);

}  // namespace garmcap::daemon
