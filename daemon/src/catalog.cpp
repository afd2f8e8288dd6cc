#include "garmcap/daemon/catalog.h"

#include <spdlog/spdlog.h>
#include <sqlite3.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <ctime>

#include "garmcap/daemon/disk_full.h"
#include "garmcap/daemon/review_policy.h"

namespace garmcap::daemon {

namespace {
// SQLITE_FULL, or an I/O error whose cause is a full disk or quota: DiskFull, without the SQL.
[[noreturn]] void throwCatalogError(sqlite3* db, const std::string& message) {
  const int code = sqlite3_extended_errcode(db);
  const int sys = sqlite3_system_errno(db);
  if ((code & 0xff) == SQLITE_FULL ||
      ((code & 0xff) == SQLITE_IOERR && (sys == ENOSPC || sys == EDQUOT)))
    throw DiskFull("catalog");
  if ((code & 0xff) == SQLITE_READONLY)  // opened read-only because the disk was full
    throw DiskFull("catalog opened read-only");
  throw CatalogError(message);
}
}  // namespace

namespace {

// Version 1: the first released layout (no review status, warnings, size guide or job frames).
constexpr const char* kSchemaV1 = R"sql(
CREATE TABLE images(
  sha256 TEXT PRIMARY KEY CHECK(length(sha256) = 64),
  media_type TEXT NOT NULL,
  bytes INTEGER NOT NULL,
  created_at TEXT NOT NULL);
CREATE TABLE calibrations(
  id INTEGER PRIMARY KEY,
  created_at TEXT NOT NULL,
  empty_sha256 TEXT NOT NULL REFERENCES images(sha256),
  json TEXT NOT NULL);
CREATE TABLE jobs(
  id INTEGER PRIMARY KEY,
  kind TEXT NOT NULL,
  state TEXT NOT NULL CHECK(state IN ('queued','running','done','failed')),
  stage TEXT NOT NULL DEFAULT '',
  progress REAL NOT NULL DEFAULT 0,
  item_id INTEGER,
  calibration_id INTEGER REFERENCES calibrations(id),
  error TEXT NOT NULL DEFAULT '',
  created_at TEXT NOT NULL,
  updated_at TEXT NOT NULL);
CREATE TABLE items(
  id INTEGER PRIMARY KEY,
  sku TEXT NOT NULL DEFAULT '',
  title TEXT NOT NULL DEFAULT '',
  price_cents INTEGER,
  tags TEXT NOT NULL DEFAULT '[]',
  notes TEXT NOT NULL DEFAULT '',
  status TEXT NOT NULL DEFAULT 'draft',
  type TEXT NOT NULL DEFAULT '',
  attributes TEXT NOT NULL DEFAULT '{}',
  confidence REAL NOT NULL DEFAULT 0,
  calibration_id INTEGER REFERENCES calibrations(id),
  job_id INTEGER REFERENCES jobs(id),
  created_at TEXT NOT NULL,
  updated_at TEXT NOT NULL,
  deleted_at TEXT);
CREATE TABLE measurements(
  item_id INTEGER NOT NULL REFERENCES items(id) ON DELETE CASCADE,
  name TEXT NOT NULL,
  value_cm REAL NOT NULL,
  PRIMARY KEY(item_id, name));
CREATE TABLE item_images(
  item_id INTEGER NOT NULL REFERENCES items(id) ON DELETE CASCADE,
  kind TEXT NOT NULL,
  sha256 TEXT NOT NULL REFERENCES images(sha256),
  PRIMARY KEY(item_id, kind));
CREATE TABLE patterns(
  item_id INTEGER NOT NULL REFERENCES items(id) ON DELETE CASCADE,
  size TEXT NOT NULL,
  json TEXT NOT NULL,
  PRIMARY KEY(item_id, size));
CREATE INDEX items_sku ON items(sku);
)sql";

// Version 2: review status, warnings, base size, size guide, result.json and stored job frames.
constexpr const char* kMigrateV1ToV2 = R"sql(
ALTER TABLE items ADD COLUMN warnings TEXT NOT NULL DEFAULT '[]';
ALTER TABLE items ADD COLUMN base_size TEXT NOT NULL DEFAULT '';
ALTER TABLE items ADD COLUMN size_guide TEXT;
ALTER TABLE items ADD COLUMN result TEXT;
UPDATE items SET status = CASE status WHEN 'active' THEN 'approved' WHEN 'archived' THEN 'rejected'
                                      ELSE 'needs_review' END;
ALTER TABLE jobs ADD COLUMN sku TEXT NOT NULL DEFAULT '';
ALTER TABLE jobs ADD COLUMN empty_sha256 TEXT NOT NULL DEFAULT '';
ALTER TABLE jobs ADD COLUMN dressed_sha256 TEXT NOT NULL DEFAULT '';
CREATE INDEX items_type ON items(type);
CREATE INDEX jobs_state ON jobs(state);
)sql";

// Version 3: the outbox of changes for the hub (docs/hub.md), written in the transaction of the
// change itself, and the pusher's small state (the hub's change cursor). AUTOINCREMENT: a
// sequence id is never reused, even after the newest row was sent and removed. The items a station
// already holds are queued once, so that a station joining a hub sends its whole catalog. Also
// the settings staff and shop owners save from the web UI (the shop's setup), as JSON per key.
constexpr const char* kMigrateV2ToV3 = R"sql(
CREATE TABLE outbox(
  seq INTEGER PRIMARY KEY AUTOINCREMENT,
  kind TEXT NOT NULL CHECK(kind IN ('item_upsert','item_delete')),
  item_id INTEGER NOT NULL,
  created_at TEXT NOT NULL);
CREATE TABLE hub_state(
  key TEXT PRIMARY KEY,
  value TEXT NOT NULL);
INSERT INTO outbox(kind, item_id, created_at)
  SELECT 'item_upsert', id, updated_at FROM items WHERE deleted_at IS NULL ORDER BY id;
CREATE TABLE settings(
  key TEXT PRIMARY KEY,
  value TEXT NOT NULL,
  updated_at TEXT NOT NULL);
)sql";

// Version 4: the shop's tape measurements (issue 15 part 7). Each row keeps, beside the taped
// value, the item's type and the pipeline's uncorrected reading at the time of taping, so the
// corrections fitted from them do not drift as corrections change later captures, re-runs or
// staff edits. Rows go with the item when it is purged (CASCADE); a soft-deleted item's rows stay
// but are not fitted on.
constexpr const char* kMigrateV3ToV4 = R"sql(
CREATE TABLE tape_measurements(
  item_id INTEGER NOT NULL REFERENCES items(id) ON DELETE CASCADE,
  name TEXT NOT NULL,
  type TEXT NOT NULL,
  tape_cm REAL NOT NULL CHECK(tape_cm > 0),
  measured_cm REAL NOT NULL CHECK(measured_cm > 0),
  created_at TEXT NOT NULL,
  PRIMARY KEY(item_id, name));
CREATE INDEX tape_measurements_type ON tape_measurements(type, name);
)sql";

// Version 5: outbox rows the hub refused for good (a 4xx that a retry cannot change, issue 20),
// parked here with the hub's answer so that the rows behind them are sent and staff can see why.
// A row moves from outbox to here in one transaction; nothing here is retried by itself.
constexpr const char* kMigrateV4ToV5 = R"sql(
CREATE TABLE outbox_refused(
  seq INTEGER PRIMARY KEY,
  kind TEXT NOT NULL,
  item_id INTEGER NOT NULL,
  created_at TEXT NOT NULL,
  http_status INTEGER NOT NULL,
  reason TEXT NOT NULL,
  refused_at TEXT NOT NULL);
)sql";

// Version 6: blobs are reclaimed (docs/daemon.md, "Storage"): finding the rows that still name a
// blob must not scan every item's images or every job.
constexpr const char* kMigrateV5ToV6 = R"sql(
CREATE INDEX item_images_sha256 ON item_images(sha256);
CREATE INDEX jobs_dressed_sha256 ON jobs(dressed_sha256);
CREATE INDEX jobs_empty_sha256 ON jobs(empty_sha256);
CREATE INDEX calibrations_empty_sha256 ON calibrations(empty_sha256);
)sql";

const char* text(sqlite3_stmt* s, int col) {
  const unsigned char* t = sqlite3_column_text(s, col);
  return t ? reinterpret_cast<const char*>(t) : "";
}

// Milliseconds, fixed width: timestamps compare as strings (the queued-job expiry relies on it).
std::string isoUtc(std::chrono::system_clock::time_point t) {
  const std::time_t tt = std::chrono::system_clock::to_time_t(t);
  const auto ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(t.time_since_epoch()).count() % 1000;
  std::tm tm{};
  gmtime_r(&tt, &tm);
  char buf[40];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &tm);
  char out[48];
  std::snprintf(out, sizeof out, "%s.%03dZ", buf, static_cast<int>(ms));
  return out;
}

nlohmann::json jsonColumn(sqlite3_stmt* s, int col, nlohmann::json fallback) {
  if (sqlite3_column_type(s, col) == SQLITE_NULL)
    return fallback;
  auto parsed = nlohmann::json::parse(text(s, col), nullptr, false);
  return parsed.is_discarded() ? fallback : parsed;
}

}  // namespace

std::string catalogSchemaSql(int version) {
  if (version == 1)
    return kSchemaV1;
  if (version == 2)
    return std::string(kSchemaV1) + kMigrateV1ToV2;
  if (version == 3)
    return std::string(kSchemaV1) + kMigrateV1ToV2 + kMigrateV2ToV3;
  if (version == 4)
    return std::string(kSchemaV1) + kMigrateV1ToV2 + kMigrateV2ToV3 + kMigrateV3ToV4;
  if (version == 5)
    return std::string(kSchemaV1) + kMigrateV1ToV2 + kMigrateV2ToV3 + kMigrateV3ToV4 +
           kMigrateV4ToV5;
  if (version == 6)
    return std::string(kSchemaV1) + kMigrateV1ToV2 + kMigrateV2ToV3 + kMigrateV3ToV4 +
           kMigrateV4ToV5 + kMigrateV5ToV6;
  throw CatalogError("no catalog schema version " + std::to_string(version));
}

// RAII prepared statement: bound parameters only, reset on destruction.
class Catalog::Statement {
 public:
  Statement(Catalog& c, const char* sql) : db_(c.db_), sql_(sql) {
    if (sqlite3_prepare_v2(db_, sql, -1, &stmt_, nullptr) != SQLITE_OK)
      throw CatalogError(std::string("catalog: cannot prepare '") + sql +
                         "': " + sqlite3_errmsg(db_));
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  Statement& bind(int i, std::int64_t v) {
    check(sqlite3_bind_int64(stmt_, i, v));
    return *this;
  }
  Statement& bind(int i, int v) { return bind(i, static_cast<std::int64_t>(v)); }
  Statement& bind(int i, double v) {
    check(sqlite3_bind_double(stmt_, i, v));
    return *this;
  }
  Statement& bind(int i, const std::string& v) {
    check(sqlite3_bind_text(stmt_, i, v.data(), static_cast<int>(v.size()), SQLITE_TRANSIENT));
    return *this;
  }
  Statement& bind(int i, const char* v) { return bind(i, std::string(v)); }
  Statement& bind(int i, std::optional<std::int64_t> v) {
    if (v)
      return bind(i, *v);
    check(sqlite3_bind_null(stmt_, i));
    return *this;
  }
  Statement& bindNull(int i) {
    check(sqlite3_bind_null(stmt_, i));
    return *this;
  }
  /// Steps once; true when a row is available.
  bool step() {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW)
      return true;
    if (rc == SQLITE_DONE)
      return false;
    throwCatalogError(db_, std::string("catalog: '") + sql_ + "' failed: " + sqlite3_errmsg(db_));
  }
  void run() {
    while (step()) {
    }
  }
  sqlite3_stmt* get() { return stmt_; }

 private:
  void check(int rc) {
    if (rc != SQLITE_OK)
      throw CatalogError(std::string("catalog: bind failed for '") + sql_ +
                         "': " + sqlite3_errmsg(db_));
  }
  sqlite3* db_;
  const char* sql_;
  sqlite3_stmt* stmt_ = nullptr;
};

namespace {
// Rolls back unless committed (SQLiteCpp's Transaction semantics).
class Transaction {
 public:
  explicit Transaction(sqlite3* db) : db_(db) {
    char* err = nullptr;
    if (sqlite3_exec(db_, "BEGIN IMMEDIATE", nullptr, nullptr, &err) != SQLITE_OK) {
      std::string msg = err ? err : "?";
      sqlite3_free(err);
      throwCatalogError(db_, "catalog: cannot begin a transaction: " + msg);
    }
  }
  ~Transaction() {
    if (!done_)
      sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
  }
  void commit() {
    char* err = nullptr;
    if (sqlite3_exec(db_, "COMMIT", nullptr, nullptr, &err) != SQLITE_OK) {
      std::string msg = err ? err : "?";
      sqlite3_free(err);
      throwCatalogError(db_, "catalog: commit failed: " + msg);
    }
    done_ = true;
  }

 private:
  sqlite3* db_;
  bool done_ = false;
};
}  // namespace

Catalog::Catalog(const std::filesystem::path& file, Mode mode) : file_(file) {
  const bool readOnly = mode == Mode::kReadOnly;
  if (readOnly && !std::filesystem::exists(file))
    throw CatalogError("catalog: " + file.string() +
                       " does not exist (cannot create it read-only)");
  const std::string uri = "file:" + file.string() + "?immutable=1";
  const int rc =
      readOnly
          ? sqlite3_open_v2(uri.c_str(), &db_,
                            SQLITE_OPEN_READONLY | SQLITE_OPEN_URI | SQLITE_OPEN_FULLMUTEX, nullptr)
          : sqlite3_open_v2(file.c_str(), &db_,
                            SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX,
                            nullptr);
  if (rc != SQLITE_OK) {
    std::string msg = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    db_ = nullptr;
    throw CatalogError("catalog: cannot open " + file.string() + ": " + msg);
  }
  try {
    sqlite3_extended_result_codes(db_, 1);
    sqlite3_busy_timeout(db_, 5000);
    exec("PRAGMA foreign_keys = ON");
    if (readOnly) {
      readOnly_ = true;
      checkReadable();
    } else {
      exec("PRAGMA journal_mode = WAL");
      exec("PRAGMA synchronous = FULL");
      migrate();
    }
  } catch (...) {
    sqlite3_close(db_);
    db_ = nullptr;
    throw;
  }
}

Catalog::~Catalog() {
  if (db_)
    sqlite3_close(db_);
}

void Catalog::checkReadable() {
  int appId = 0;
  {
    Statement s(*this, "PRAGMA application_id");
    if (s.step())
      appId = sqlite3_column_int(s.get(), 0);
  }
  if (appId != kCatalogApplicationId)
    throw CatalogError("catalog " + file_.string() + ": not a GarmCap catalog (application_id " +
                       std::to_string(appId) + ")");
  if (schemaVersion() != kCatalogSchemaVersion)
    throw CatalogError("catalog " + file_.string() + ": schema version " +
                       std::to_string(schemaVersion()) + " cannot be migrated read-only (this " +
                       "garmcapd needs " + std::to_string(kCatalogSchemaVersion) + ")");
}

void Catalog::exec(const char* sql) {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &err) != SQLITE_OK) {
    std::string msg = err ? err : sqlite3_errmsg(db_);
    sqlite3_free(err);
    throwCatalogError(db_, "catalog " + file_.string() + ": '" + std::string(sql).substr(0, 60) +
                               "' failed: " + msg);
  }
}

int Catalog::schemaVersion() const {
  sqlite3_stmt* s = nullptr;
  sqlite3_prepare_v2(db_, "PRAGMA user_version", -1, &s, nullptr);
  int v = -1;
  if (s && sqlite3_step(s) == SQLITE_ROW)
    v = sqlite3_column_int(s, 0);
  sqlite3_finalize(s);
  return v;
}

void Catalog::migrate() {
  int appId = 0;
  {
    Statement s(*this, "PRAGMA application_id");
    if (s.step())
      appId = sqlite3_column_int(s.get(), 0);
  }
  int version = schemaVersion();
  bool empty = true;
  {
    Statement s(*this, "SELECT count(*) FROM sqlite_master");
    if (s.step())
      empty = sqlite3_column_int(s.get(), 0) == 0;
  }
  if (empty && version == 0) {
    Transaction t(db_);
    exec(kSchemaV1);
    exec(("PRAGMA application_id = " + std::to_string(kCatalogApplicationId)).c_str());
    exec("PRAGMA user_version = 1");
    t.commit();
    version = 1;
    appId = kCatalogApplicationId;
  }
  if (appId != kCatalogApplicationId)
    throw CatalogError("catalog " + file_.string() + ": not a GarmCap catalog (application_id " +
                       std::to_string(appId) + ")");
  if (version > kCatalogSchemaVersion)
    throw CatalogError("catalog " + file_.string() + ": schema version " + std::to_string(version) +
                       " is newer than this garmcapd (" + std::to_string(kCatalogSchemaVersion) +
                       "); refusing to open it");
  if (version < 1)
    throw CatalogError("catalog " + file_.string() + ": bad schema version " +
                       std::to_string(version));
  // Ordered migrations, each in its own transaction together with its user_version.
  static const std::vector<const char*> kMigrations = {
      kMigrateV1ToV2, kMigrateV2ToV3, kMigrateV3ToV4, kMigrateV4ToV5, kMigrateV5ToV6};
  while (version < kCatalogSchemaVersion) {
    spdlog::info("catalog: migrating {} from schema {} to {}", file_.string(), version,
                 version + 1);
    Transaction t(db_);
    exec(kMigrations[static_cast<std::size_t>(version - 1)]);
    exec(("PRAGMA user_version = " + std::to_string(version + 1)).c_str());
    t.commit();
    ++version;
  }
}

std::string Catalog::integrityCheck() {
  Statement s(*this, "PRAGMA integrity_check");
  std::string out;
  while (s.step()) {
    if (!out.empty())
      out += "; ";
    out += text(s.get(), 0);
  }
  return out;
}

std::string Catalog::now() const {
  return isoUtc(std::chrono::system_clock::now());
}

// --- images ----------------------------------------------------------------------------------

void Catalog::addImage(const std::string& sha256, const std::string& mediaType,
                       std::int64_t bytes) {
  Statement(*this,
            "INSERT OR IGNORE INTO images(sha256, media_type, bytes, created_at) VALUES(?,?,?,?)")
      .bind(1, sha256)
      .bind(2, mediaType)
      .bind(3, bytes)
      .bind(4, now())
      .run();
}

std::optional<std::string> Catalog::imageMediaType(const std::string& sha256) {
  Statement s(*this, "SELECT media_type FROM images WHERE sha256 = ?");
  s.bind(1, sha256);
  if (!s.step())
    return std::nullopt;
  return std::string(text(s.get(), 0));
}

std::set<std::string> Catalog::referencedImages() {
  std::set<std::string> out;
  Statement s(*this, "SELECT sha256 FROM images");
  while (s.step())
    out.insert(text(s.get(), 0));
  return out;
}

namespace {
// A row that still needs the blob: an item's image (live or soft-deleted: it can be restored), a
// calibration's bare frame, a job's frames (a re-run starts from them).
constexpr const char* kBlobStillNamed =
    "SELECT EXISTS(SELECT 1 FROM item_images WHERE sha256 = ?1) "
    "OR EXISTS(SELECT 1 FROM calibrations WHERE empty_sha256 = ?1) "
    "OR EXISTS(SELECT 1 FROM jobs WHERE dressed_sha256 = ?1 OR empty_sha256 = ?1)";
}  // namespace

std::vector<std::string> Catalog::dropUnreferencedImages(
    std::optional<std::vector<std::string>> candidates) {
  Transaction t(db_);
  if (!candidates) {
    candidates.emplace();
    Statement s(*this, "SELECT sha256 FROM images");
    while (s.step())
      candidates->push_back(text(s.get(), 0));
  }
  std::sort(candidates->begin(), candidates->end());
  candidates->erase(std::unique(candidates->begin(), candidates->end()), candidates->end());
  std::vector<std::string> dropped;
  for (const std::string& sha : *candidates) {
    Statement named(*this, kBlobStillNamed);
    named.bind(1, sha);
    if (named.step() && sqlite3_column_int(named.get(), 0) != 0)
      continue;
    Statement(*this, "DELETE FROM images WHERE sha256 = ?").bind(1, sha).run();
    if (sqlite3_changes(db_) > 0)
      dropped.push_back(sha);
  }
  t.commit();
  return dropped;
}

std::vector<std::string> Catalog::purgeDeletedItems(std::chrono::system_clock::time_point cutoff,
                                                    bool keepUntilHubKnows) {
  Transaction t(db_);
  std::vector<std::int64_t> ids;
  {
    Statement s(*this,
                "SELECT id FROM items WHERE deleted_at IS NOT NULL AND deleted_at < ?1 AND "
                "(?2 = 0 OR NOT EXISTS(SELECT 1 FROM outbox WHERE outbox.item_id = items.id))");
    s.bind(1, isoUtc(cutoff));
    s.bind(2, keepUntilHubKnows ? 1 : 0);
    while (s.step())
      ids.push_back(sqlite3_column_int64(s.get(), 0));
  }
  std::vector<std::string> released;
  for (std::int64_t id : ids) {
    {
      Statement s(*this,
                  "SELECT sha256 FROM item_images WHERE item_id = ?1 UNION "
                  "SELECT dressed_sha256 FROM jobs WHERE item_id = ?1 OR id = (SELECT job_id FROM "
                  "items WHERE id = ?1) UNION "
                  "SELECT empty_sha256 FROM jobs WHERE item_id = ?1 OR id = (SELECT job_id FROM "
                  "items WHERE id = ?1)");
      s.bind(1, id);
      while (s.step())
        if (std::string sha = text(s.get(), 0); !sha.empty())
          released.push_back(std::move(sha));
    }
    // The item's jobs stay (the job list is history) but no longer hold its frames.
    Statement(*this,
              "UPDATE jobs SET dressed_sha256 = '', empty_sha256 = '' WHERE item_id = ?1 OR id = "
              "(SELECT job_id FROM items WHERE id = ?1)")
        .bind(1, id)
        .run();
    // Without a hub nothing reads the outbox: its rows for the item go with it.
    Statement(*this, "DELETE FROM outbox WHERE item_id = ?").bind(1, id).run();
    Statement(*this, "DELETE FROM items WHERE id = ?").bind(1, id).run();  // cascades
  }
  t.commit();
  return released;
}

std::vector<std::string> Catalog::forgetFailedJobFrames(
    std::chrono::system_clock::time_point cutoff) {
  Transaction t(db_);
  std::vector<std::string> released;
  {
    Statement s(*this,
                "SELECT dressed_sha256, empty_sha256 FROM jobs WHERE state = 'failed' AND "
                "updated_at < ? AND (dressed_sha256 != '' OR empty_sha256 != '')");
    s.bind(1, isoUtc(cutoff));
    while (s.step())
      for (int col : {0, 1})
        if (std::string sha = text(s.get(), col); !sha.empty())
          released.push_back(std::move(sha));
  }
  Statement(*this,
            "UPDATE jobs SET dressed_sha256 = '', empty_sha256 = '' WHERE state = 'failed' AND "
            "updated_at < ? AND (dressed_sha256 != '' OR empty_sha256 != '')")
      .bind(1, isoUtc(cutoff))
      .run();
  t.commit();
  return released;
}

// --- calibrations ------------------------------------------------------------------------------

std::int64_t Catalog::addCalibration(const std::string& emptySha256, const nlohmann::json& json) {
  Statement(*this, "INSERT INTO calibrations(created_at, empty_sha256, json) VALUES(?,?,?)")
      .bind(1, now())
      .bind(2, emptySha256)
      .bind(3, json.dump())
      .run();
  return sqlite3_last_insert_rowid(db_);
}

namespace {
Calibration readCalibration(sqlite3_stmt* s) {
  Calibration c;
  c.id = sqlite3_column_int64(s, 0);
  c.createdAt = text(s, 1);
  c.emptySha256 = text(s, 2);
  c.json = jsonColumn(s, 3, nlohmann::json::object());
  return c;
}
}  // namespace

std::optional<Calibration> Catalog::latestCalibration() {
  Statement s(*this,
              "SELECT id, created_at, empty_sha256, json FROM calibrations ORDER BY id DESC "
              "LIMIT 1");
  if (!s.step())
    return std::nullopt;
  return readCalibration(s.get());
}

std::optional<Calibration> Catalog::calibration(std::int64_t id) {
  Statement s(*this, "SELECT id, created_at, empty_sha256, json FROM calibrations WHERE id = ?");
  s.bind(1, id);
  if (!s.step())
    return std::nullopt;
  return readCalibration(s.get());
}

// --- settings --------------------------------------------------------------------------------

std::optional<nlohmann::json> Catalog::setting(const std::string& key) {
  Statement s(*this, "SELECT value FROM settings WHERE key = ?");
  s.bind(1, key);
  if (!s.step())
    return std::nullopt;
  auto parsed = nlohmann::json::parse(text(s.get(), 0), nullptr, false);
  if (parsed.is_discarded())
    throw CatalogError("catalog " + file_.string() + ": setting '" + key + "' is not JSON");
  return parsed;
}

void Catalog::setSetting(const std::string& key, const nlohmann::json& value) {
  Statement(
      *this,
      "INSERT INTO settings(key, value, updated_at) VALUES(?,?,?) "
      "ON CONFLICT(key) DO UPDATE SET value = excluded.value, updated_at = excluded.updated_at")
      .bind(1, key)
      .bind(2, value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace))
      .bind(3, now())
      .run();
}

// --- tape measurements -----------------------------------------------------------------------

void Catalog::setTape(std::int64_t itemId, const std::vector<TapeEntry>& entries) {
  Transaction t(db_);
  const std::string ts = now();
  for (const auto& e : entries)
    Statement(*this,
              "INSERT INTO tape_measurements(item_id, name, type, tape_cm, measured_cm, "
              "created_at) VALUES(?,?,?,?,?,?) ON CONFLICT(item_id, name) DO UPDATE SET "
              "type = excluded.type, tape_cm = excluded.tape_cm, measured_cm = "
              "excluded.measured_cm, created_at = excluded.created_at")
        .bind(1, itemId)
        .bind(2, e.name)
        .bind(3, e.type)
        .bind(4, e.tapeCm)
        .bind(5, e.measuredCm)
        .bind(6, ts)
        .run();
  t.commit();
}

std::vector<TapeEntry> Catalog::tapes(std::optional<std::int64_t> itemId) {
  Statement s(*this,
              "SELECT t.item_id, t.name, t.type, t.tape_cm, t.measured_cm, t.created_at "
              "FROM tape_measurements t JOIN items i ON i.id = t.item_id "
              "WHERE i.deleted_at IS NULL AND (?1 IS NULL OR t.item_id = ?1) "
              "ORDER BY t.type, t.name, t.item_id");
  s.bind(1, itemId);
  std::vector<TapeEntry> out;
  while (s.step()) {
    TapeEntry e;
    e.itemId = sqlite3_column_int64(s.get(), 0);
    e.name = text(s.get(), 1);
    e.type = text(s.get(), 2);
    e.tapeCm = sqlite3_column_double(s.get(), 3);
    e.measuredCm = sqlite3_column_double(s.get(), 4);
    e.createdAt = text(s.get(), 5);
    out.push_back(std::move(e));
  }
  return out;
}

int Catalog::deleteTape(std::int64_t itemId) {
  Statement s(*this, "DELETE FROM tape_measurements WHERE item_id = ?");
  s.bind(1, itemId).run();
  return sqlite3_changes(db_);
}

// --- jobs ------------------------------------------------------------------------------------

nlohmann::json Job::toJson() const {
  nlohmann::json j{{"id", id},
                   {"kind", kind},
                   {"state", state},
                   {"stage", stage},
                   {"progress", progress},
                   {"error", error},
                   {"created_at", createdAt},
                   {"updated_at", updatedAt}};
  j["item_id"] = itemId ? nlohmann::json(*itemId) : nlohmann::json(nullptr);
  j["calibration_id"] = calibrationId ? nlohmann::json(*calibrationId) : nlohmann::json(nullptr);
  if (!sku.empty())
    j["sku"] = sku;
  return j;
}

std::int64_t Catalog::addJob(const std::string& kind, const std::string& sku,
                             std::optional<std::int64_t> itemId) {
  const std::string t = now();
  Statement(*this,
            "INSERT INTO jobs(kind, state, stage, progress, sku, item_id, created_at, updated_at) "
            "VALUES(?, 'queued', 'queued', 0, ?, ?, ?, ?)")
      .bind(1, kind)
      .bind(2, sku)
      .bind(3, itemId)
      .bind(4, t)
      .bind(5, t)
      .run();
  return sqlite3_last_insert_rowid(db_);
}

namespace {
// Each column once: its name and how it is read; the SELECT and the reader come from this list.
template <class Row>
struct Column {
  const char* name;
  void (*read)(sqlite3_stmt* s, int col, Row& row);
};

template <class Row, std::size_t N>
std::string selectFrom(const std::array<Column<Row>, N>& columns, const char* table) {
  std::string sql = "SELECT ";
  for (std::size_t i = 0; i < N; ++i)
    sql += std::string(i ? ", " : "") + columns[i].name;
  return sql + " FROM " + table + " ";
}

template <class Row, std::size_t N>
Row readRow(const std::array<Column<Row>, N>& columns, sqlite3_stmt* s) {
  Row row;
  for (std::size_t i = 0; i < N; ++i)
    columns[i].read(s, static_cast<int>(i), row);
  return row;
}

std::optional<std::int64_t> optionalInt(sqlite3_stmt* s, int col) {
  if (sqlite3_column_type(s, col) == SQLITE_NULL)
    return std::nullopt;
  return sqlite3_column_int64(s, col);
}

const std::array<Column<Job>, 13> kJobColumns = {{
    {"id", [](sqlite3_stmt* s, int c, Job& j) { j.id = sqlite3_column_int64(s, c); }},
    {"kind", [](sqlite3_stmt* s, int c, Job& j) { j.kind = text(s, c); }},
    {"state", [](sqlite3_stmt* s, int c, Job& j) { j.state = text(s, c); }},
    {"stage", [](sqlite3_stmt* s, int c, Job& j) { j.stage = text(s, c); }},
    {"progress", [](sqlite3_stmt* s, int c, Job& j) { j.progress = sqlite3_column_double(s, c); }},
    {"item_id", [](sqlite3_stmt* s, int c, Job& j) { j.itemId = optionalInt(s, c); }},
    {"calibration_id", [](sqlite3_stmt* s, int c, Job& j) { j.calibrationId = optionalInt(s, c); }},
    {"error", [](sqlite3_stmt* s, int c, Job& j) { j.error = text(s, c); }},
    {"sku", [](sqlite3_stmt* s, int c, Job& j) { j.sku = text(s, c); }},
    {"empty_sha256", [](sqlite3_stmt* s, int c, Job& j) { j.emptySha256 = text(s, c); }},
    {"dressed_sha256", [](sqlite3_stmt* s, int c, Job& j) { j.dressedSha256 = text(s, c); }},
    {"created_at", [](sqlite3_stmt* s, int c, Job& j) { j.createdAt = text(s, c); }},
    {"updated_at", [](sqlite3_stmt* s, int c, Job& j) { j.updatedAt = text(s, c); }},
}};

const std::string& jobSelect() {
  static const std::string sql = selectFrom(kJobColumns, "jobs");
  return sql;
}

Job readJob(sqlite3_stmt* s) {
  return readRow(kJobColumns, s);
}
}  // namespace

std::optional<Job> Catalog::job(std::int64_t id) {
  const std::string sql = jobSelect() + "WHERE id = ?";
  Statement s(*this, sql.c_str());
  s.bind(1, id);
  if (!s.step())
    return std::nullopt;
  return readJob(s.get());
}

std::vector<Job> Catalog::recentJobs(int limit) {
  const std::string sql = jobSelect() + "ORDER BY id DESC LIMIT ?";
  Statement s(*this, sql.c_str());
  s.bind(1, limit);
  std::vector<Job> out;
  while (s.step())
    out.push_back(readJob(s.get()));
  return out;
}

void Catalog::updateJob(std::int64_t id, const std::string& state, const std::string& stage,
                        double progress) {
  Statement(*this,
            "UPDATE jobs SET state = ?, stage = ?, progress = ?, updated_at = ? WHERE id = ?")
      .bind(1, state)
      .bind(2, stage)
      .bind(3, progress)
      .bind(4, now())
      .bind(5, id)
      .run();
}

void Catalog::setJobFrames(std::int64_t id, const std::string& emptySha256,
                           const std::string& dressedSha256) {
  Statement(*this,
            "UPDATE jobs SET empty_sha256 = ?, dressed_sha256 = ?, updated_at = ? WHERE id = ?")
      .bind(1, emptySha256)
      .bind(2, dressedSha256)
      .bind(3, now())
      .bind(4, id)
      .run();
}

void Catalog::failJob(std::int64_t id, const std::string& error) {
  Statement(*this, "UPDATE jobs SET state = 'failed', error = ?, updated_at = ? WHERE id = ?")
      .bind(1, error)
      .bind(2, now())
      .bind(3, id)
      .run();
}

void Catalog::finishJob(std::int64_t id, std::optional<std::int64_t> itemId,
                        std::optional<std::int64_t> calibrationId) {
  Statement(*this,
            "UPDATE jobs SET state = 'done', stage = 'done', progress = 1, item_id = ?, "
            "calibration_id = ?, error = '', updated_at = ? WHERE id = ?")
      .bind(1, itemId)
      .bind(2, calibrationId)
      .bind(3, now())
      .bind(4, id)
      .run();
}

std::vector<std::int64_t> Catalog::failInterruptedJobs(const std::string& reason) {
  std::vector<std::int64_t> ids;
  {
    Statement s(*this, "SELECT id FROM jobs WHERE state = 'running' ORDER BY id");
    while (s.step())
      ids.push_back(sqlite3_column_int64(s.get(), 0));
  }
  Statement(*this,
            "UPDATE jobs SET state = 'failed', error = ? || ' (during ' || stage || ')', "
            "updated_at = ? WHERE state = 'running'")
      .bind(1, reason)
      .bind(2, now())
      .run();
  return ids;
}

std::vector<std::int64_t> Catalog::expireQueuedJobs(std::chrono::seconds maxAge,
                                                    const std::string& reason) {
  const std::string cutoff = isoUtc(std::chrono::system_clock::now() - maxAge);
  std::vector<std::int64_t> ids;
  {
    Statement s(*this, "SELECT id FROM jobs WHERE state = 'queued' AND created_at < ? ORDER BY id");
    s.bind(1, cutoff);
    while (s.step())
      ids.push_back(sqlite3_column_int64(s.get(), 0));
  }
  Statement(*this,
            "UPDATE jobs SET state = 'failed', error = ?, updated_at = ? "
            "WHERE state = 'queued' AND created_at < ?")
      .bind(1, reason)
      .bind(2, now())
      .bind(3, cutoff)
      .run();
  return ids;
}

std::vector<Job> Catalog::queuedJobs() {
  const std::string sql = jobSelect() + "WHERE state = 'queued' ORDER BY id";
  Statement s(*this, sql.c_str());
  std::vector<Job> out;
  while (s.step())
    out.push_back(readJob(s.get()));
  return out;
}

// --- items -----------------------------------------------------------------------------------

nlohmann::json Item::toJson() const {
  nlohmann::json j{{"id", id},
                   {"sku", sku},
                   {"title", title},
                   {"tags", tags},
                   {"notes", notes},
                   {"status", status},
                   {"type", type},
                   {"attributes", attributes},
                   {"confidence", confidence},
                   {"warnings", warnings},
                   {"checks", checksOf(warnings)},
                   {"measurements", measurementsCm},
                   {"units", "cm"},
                   {"sizes", sizes},
                   {"base_size", baseSize},
                   {"created_at", createdAt},
                   {"updated_at", updatedAt}};
  j["price_cents"] = priceCents ? nlohmann::json(*priceCents) : nlohmann::json(nullptr);
  j["calibration_id"] = calibrationId ? nlohmann::json(*calibrationId) : nlohmann::json(nullptr);
  j["job_id"] = jobId ? nlohmann::json(*jobId) : nlohmann::json(nullptr);
  j["deleted_at"] = deletedAt ? nlohmann::json(*deletedAt) : nlohmann::json(nullptr);
  nlohmann::json images = nlohmann::json::object();
  for (const auto& im : this->images)
    images[im.kind] = {{"url", "/api/items/" + std::to_string(id) + "/images/" + im.kind},
                       {"sha256", im.sha256},
                       {"media_type", im.mediaType}};
  j["images"] = images;
  return j;
}

namespace {
std::vector<std::string> stringsOf(const nlohmann::json& array) {
  std::vector<std::string> out;
  for (const auto& v : array)
    if (v.is_string())
      out.push_back(v.get<std::string>());
  return out;
}

const std::array<Column<Item>, 17> kItemColumns = {{
    {"id", [](sqlite3_stmt* s, int c, Item& it) { it.id = sqlite3_column_int64(s, c); }},
    {"sku", [](sqlite3_stmt* s, int c, Item& it) { it.sku = text(s, c); }},
    {"title", [](sqlite3_stmt* s, int c, Item& it) { it.title = text(s, c); }},
    {"price_cents", [](sqlite3_stmt* s, int c, Item& it) { it.priceCents = optionalInt(s, c); }},
    {"tags", [](sqlite3_stmt* s, int c,
                Item& it) { it.tags = stringsOf(jsonColumn(s, c, nlohmann::json::array())); }},
    {"notes", [](sqlite3_stmt* s, int c, Item& it) { it.notes = text(s, c); }},
    {"status", [](sqlite3_stmt* s, int c, Item& it) { it.status = text(s, c); }},
    {"type", [](sqlite3_stmt* s, int c, Item& it) { it.type = text(s, c); }},
    {"attributes",
     [](sqlite3_stmt* s, int c, Item& it) {
       const nlohmann::json attributes = jsonColumn(s, c, nlohmann::json::object());
       for (const auto& [k, v] : attributes.items())
         if (v.is_string())
           it.attributes[k] = v.get<std::string>();
     }},
    {"confidence",
     [](sqlite3_stmt* s, int c, Item& it) { it.confidence = sqlite3_column_double(s, c); }},
    {"warnings",
     [](sqlite3_stmt* s, int c, Item& it) {
       it.warnings = stringsOf(jsonColumn(s, c, nlohmann::json::array()));
     }},
    {"base_size", [](sqlite3_stmt* s, int c, Item& it) { it.baseSize = text(s, c); }},
    {"calibration_id",
     [](sqlite3_stmt* s, int c, Item& it) { it.calibrationId = optionalInt(s, c); }},
    {"job_id", [](sqlite3_stmt* s, int c, Item& it) { it.jobId = optionalInt(s, c); }},
    {"created_at", [](sqlite3_stmt* s, int c, Item& it) { it.createdAt = text(s, c); }},
    {"updated_at", [](sqlite3_stmt* s, int c, Item& it) { it.updatedAt = text(s, c); }},
    {"deleted_at",
     [](sqlite3_stmt* s, int c, Item& it) {
       if (sqlite3_column_type(s, c) != SQLITE_NULL)
         it.deletedAt = std::string(text(s, c));
     }},
}};

const std::string& itemSelect() {
  static const std::string sql = selectFrom(kItemColumns, "items");
  return sql;
}

Item readItem(sqlite3_stmt* s) {
  return readRow(kItemColumns, s);
}

// The pipeline's outputs on an item row, listed once: a capture writes them (addItem), a re-run
// replaces them (replaceItemResults).
constexpr std::array<const char*, 9> kResultColumns = {"type",     "attributes",     "confidence",
                                                       "warnings", "base_size",      "size_guide",
                                                       "result",   "calibration_id", "status"};

std::string placeholders(std::size_t count) {
  std::string out;
  for (std::size_t i = 0; i < count; ++i)
    out += i ? ", ?" : "?";
  return out;
}

std::string resultColumns(const char* each) {
  std::string out;
  for (const char* name : kResultColumns)
    out += std::string(out.empty() ? "" : ", ") + name + each;
  return out;
}

/// Binds kResultColumns from `n` at `first`, `first` + 1, ...; returns the next index.
template <class Stmt>
int bindResults(Stmt& s, int first, const NewItem& n) {
  s.bind(first, n.type)
      .bind(first + 1, nlohmann::json(n.attributes).dump())
      .bind(first + 2, n.confidence)
      .bind(first + 3, nlohmann::json(n.warnings).dump())
      .bind(first + 4, n.baseSize)
      .bind(first + 5, n.sizeGuide.is_null() ? std::string("null") : n.sizeGuide.dump())
      .bind(first + 6, n.result.dump())
      .bind(first + 7, n.calibrationId)
      .bind(first + 8, n.needsReview ? kStatusNeedsReview : kStatusApproved);
  return first + static_cast<int>(kResultColumns.size());
}
}  // namespace

void Catalog::loadItemDetails(Item& item) {
  {
    Statement s(*this, "SELECT name, value_cm FROM measurements WHERE item_id = ? ORDER BY name");
    s.bind(1, item.id);
    while (s.step())
      item.measurementsCm[text(s.get(), 0)] = sqlite3_column_double(s.get(), 1);
  }
  {
    Statement s(*this,
                "SELECT ii.kind, ii.sha256, im.media_type FROM item_images ii JOIN images im ON "
                "im.sha256 = ii.sha256 WHERE ii.item_id = ? ORDER BY ii.kind");
    s.bind(1, item.id);
    while (s.step())
      item.images.push_back({text(s.get(), 0), text(s.get(), 1), text(s.get(), 2)});
  }
  {
    Statement s(*this, "SELECT size FROM patterns WHERE item_id = ? ORDER BY rowid");
    s.bind(1, item.id);
    while (s.step())
      item.sizes.push_back(text(s.get(), 0));
  }
}

// Measurements, images, patterns and the finished job of an item, shared by adding an item and
// replacing its results (the caller has removed the old measurements and patterns; an image
// kind already linked is relinked).
void Catalog::writeItemContents(std::int64_t id, const NewItem& n, const std::string& ts) {
  for (const auto& [name, cm] : n.measurementsCm)
    Statement(*this, "INSERT INTO measurements(item_id, name, value_cm) VALUES(?,?,?)")
        .bind(1, id)
        .bind(2, name)
        .bind(3, cm)
        .run();
  for (const auto& im : n.images) {
    Statement(*this,
              "INSERT OR IGNORE INTO images(sha256, media_type, bytes, created_at) VALUES(?,?,?,?)")
        .bind(1, im.sha256)
        .bind(2, im.mediaType)
        .bind(3, im.bytes)
        .bind(4, ts)
        .run();
    Statement(*this, "INSERT OR REPLACE INTO item_images(item_id, kind, sha256) VALUES(?,?,?)")
        .bind(1, id)
        .bind(2, im.kind)
        .bind(3, im.sha256)
        .run();
  }
  // The base (as measured) pattern first, then the graded sizes in the order given.
  std::vector<std::string> order;
  if (n.patterns.count("base"))
    order.push_back("base");
  for (const auto& [size, json] : n.patterns)
    if (size != "base")
      order.push_back(size);
  for (const auto& size : order)
    Statement(*this, "INSERT INTO patterns(item_id, size, json) VALUES(?,?,?)")
        .bind(1, id)
        .bind(2, size)
        .bind(3, n.patterns.at(size).dump())
        .run();
  if (n.jobId)
    Statement(*this,
              "UPDATE jobs SET state = 'done', stage = 'done', progress = 1, item_id = ?, "
              "calibration_id = ?, error = '', updated_at = ? WHERE id = ?")
        .bind(1, id)
        .bind(2, n.calibrationId)
        .bind(3, ts)
        .bind(4, *n.jobId)
        .run();
}

std::int64_t Catalog::addItem(const NewItem& n) {
  Transaction t(db_);
  const std::string ts = now();
  static const std::string insert =
      "INSERT INTO items(sku, title, job_id, created_at, updated_at, " + resultColumns("") +
      ") VALUES(?, ?, ?, ?, ?, " + placeholders(kResultColumns.size()) + ")";
  Statement insertItem(*this, insert.c_str());
  insertItem.bind(1, n.sku).bind(2, n.title).bind(3, n.jobId).bind(4, ts).bind(5, ts);
  bindResults(insertItem, 6, n);
  insertItem.run();
  const std::int64_t id = sqlite3_last_insert_rowid(db_);
  writeItemContents(id, n, ts);
  queueForHub(kOutboxUpsert, id, ts);
  t.commit();
  return id;
}

std::vector<std::string> Catalog::replaceItemResults(std::int64_t id, const NewItem& n) {
  Transaction t(db_);
  const std::string ts = now();
  std::vector<std::string> previous;
  {
    Statement s(*this, "SELECT sha256 FROM item_images WHERE item_id = ?");
    s.bind(1, id);
    while (s.step())
      previous.push_back(text(s.get(), 0));
  }
  static const std::string update =
      "UPDATE items SET " + resultColumns(" = ?") + ", updated_at = ? WHERE id = ?";
  Statement updateItem(*this, update.c_str());
  const int next = bindResults(updateItem, 1, n);
  updateItem.bind(next, ts).bind(next + 1, id).run();
  Statement(*this, "DELETE FROM measurements WHERE item_id = ?").bind(1, id).run();
  Statement(*this, "DELETE FROM patterns WHERE item_id = ?").bind(1, id).run();
  // A kind the re-run no longer makes must not keep showing the old picture.
  Statement(*this, "DELETE FROM item_images WHERE item_id = ?").bind(1, id).run();
  writeItemContents(id, n, ts);
  queueForHub(kOutboxUpsert, id, ts);
  t.commit();
  return previous;
}

std::vector<std::string> Catalog::addItemImages(std::int64_t id,
                                                const std::vector<std::string>& replaces,
                                                const std::vector<ImageRef>& images,
                                                std::optional<std::int64_t> jobId,
                                                std::optional<std::int64_t> calibrationId) {
  Transaction t(db_);
  const std::string ts = now();
  {
    Statement s(*this, "SELECT 1 FROM items WHERE id = ? AND deleted_at IS NULL");
    s.bind(1, id);
    if (!s.step())
      throw CatalogError("no item " + std::to_string(id) + " (deleted meanwhile?)");
  }
  std::vector<std::string> previous;
  for (const auto& kind : replaces) {
    Statement s(*this, "SELECT sha256 FROM item_images WHERE item_id = ? AND kind = ?");
    s.bind(1, id).bind(2, kind);
    while (s.step())
      previous.push_back(text(s.get(), 0));
    Statement(*this, "DELETE FROM item_images WHERE item_id = ? AND kind = ?")
        .bind(1, id)
        .bind(2, kind)
        .run();
  }
  NewItem n;  // images and the finished job only: no measurement, no pattern
  n.images = images;
  n.jobId = jobId;
  n.calibrationId = calibrationId;
  writeItemContents(id, n, ts);
  // The item names the job's still now; the job lets its frames go, so that a later back shot
  // replacing it releases the blob (the item's capture job keeps the frames a re-run needs).
  if (jobId)
    Statement(*this, "UPDATE jobs SET dressed_sha256 = '', empty_sha256 = '' WHERE id = ?")
        .bind(1, *jobId)
        .run();
  Statement(*this, "UPDATE items SET updated_at = ? WHERE id = ?").bind(1, ts).bind(2, id).run();
  queueForHub(kOutboxUpsert, id, ts);
  t.commit();
  return previous;
}

std::optional<Item> Catalog::item(std::int64_t id, bool includeDeleted) {
  const std::string sql =
      itemSelect() + "WHERE id = ?" + (includeDeleted ? "" : " AND deleted_at IS NULL");
  Statement s(*this, sql.c_str());
  s.bind(1, id);
  if (!s.step())
    return std::nullopt;
  Item it = readItem(s.get());
  loadItemDetails(it);
  return it;
}

std::pair<std::vector<Item>, std::int64_t> Catalog::items(const ItemQuery& q) {
  // One fixed statement; empty filters are disabled through the bound values, never by
  // building SQL from input.
  constexpr const char* kWhere =
      "WHERE ((?1 = 1 AND deleted_at IS NOT NULL) OR (?1 = 0 AND deleted_at IS NULL)) "
      "AND (?2 = '' OR type = ?2) AND (?3 = '' OR status = ?3) "
      "AND (?4 = '' OR instr(lower(sku || ' ' || title || ' ' || notes || ' ' || tags || ' ' || "
      "type || ' ' || attributes), "
      "lower(?4)) > 0) ";
  const int limit = std::clamp(q.limit, 1, 500);
  const int offset = std::max(q.offset, 0);
  std::int64_t total = 0;
  {
    const std::string sql = std::string("SELECT count(*) FROM items ") + kWhere;
    Statement s(*this, sql.c_str());
    s.bind(1, q.deleted ? 1 : 0).bind(2, q.type).bind(3, q.status).bind(4, q.search);
    if (s.step())
      total = sqlite3_column_int64(s.get(), 0);
  }
  std::vector<Item> out;
  const std::string sql = itemSelect() + kWhere + "ORDER BY id DESC LIMIT ?5 OFFSET ?6";
  Statement s(*this, sql.c_str());
  s.bind(1, q.deleted ? 1 : 0).bind(2, q.type).bind(3, q.status).bind(4, q.search);
  s.bind(5, limit).bind(6, offset);
  while (s.step())
    out.push_back(readItem(s.get()));
  for (auto& it : out)
    loadItemDetails(it);
  return {std::move(out), total};
}

bool Catalog::patchItem(std::int64_t id, const ItemPatch& p) {
  return patch(id, p, true);
}

bool Catalog::applyHubEdit(std::int64_t id, const HubEdit& e) {
  ItemPatch p;
  p.title = e.title;
  p.priceCents = e.priceCents;
  p.status = e.status;
  return patch(id, p, false);
}

bool Catalog::patch(std::int64_t id, const ItemPatch& p, bool queue) {
  if (p.status && *p.status != kStatusNeedsReview && *p.status != kStatusApproved &&
      *p.status != kStatusRejected)
    throw CatalogError("status must be needs_review, approved or rejected, got '" + *p.status +
                       "'");
  Transaction t(db_);
  {
    Statement s(*this, "SELECT 1 FROM items WHERE id = ? AND deleted_at IS NULL");
    s.bind(1, id);
    if (!s.step())
      return false;
  }
  const std::string ts = now();
  auto setText = [&](const char* sql, const std::optional<std::string>& v) {
    if (v)
      Statement(*this, sql).bind(1, *v).bind(2, ts).bind(3, id).run();
  };
  setText("UPDATE items SET sku = ?, updated_at = ? WHERE id = ?", p.sku);
  setText("UPDATE items SET title = ?, updated_at = ? WHERE id = ?", p.title);
  setText("UPDATE items SET notes = ?, updated_at = ? WHERE id = ?", p.notes);
  setText("UPDATE items SET status = ?, updated_at = ? WHERE id = ?", p.status);
  setText("UPDATE items SET type = ?, updated_at = ? WHERE id = ?", p.type);
  if (p.tags)
    setText("UPDATE items SET tags = ?, updated_at = ? WHERE id = ?",
            nlohmann::json(*p.tags).dump());
  if (p.attributes)
    setText("UPDATE items SET attributes = ?, updated_at = ? WHERE id = ?",
            nlohmann::json(*p.attributes).dump());
  if (p.priceCents)
    Statement(*this, "UPDATE items SET price_cents = ?, updated_at = ? WHERE id = ?")
        .bind(1, *p.priceCents)
        .bind(2, ts)
        .bind(3, id)
        .run();
  if (p.measurementsCm)
    for (const auto& [name, cm] : *p.measurementsCm)
      Statement(*this, "INSERT OR REPLACE INTO measurements(item_id, name, value_cm) VALUES(?,?,?)")
          .bind(1, id)
          .bind(2, name)
          .bind(3, cm)
          .run();
  if (queue)
    queueForHub(kOutboxUpsert, id, ts);
  t.commit();
  return true;
}

bool Catalog::deleteItem(std::int64_t id) {
  Transaction t(db_);
  const std::string ts = now();
  Statement(
      *this,
      "UPDATE items SET deleted_at = ?1, updated_at = ?1 WHERE id = ?2 AND deleted_at IS NULL")
      .bind(1, ts)
      .bind(2, id)
      .run();
  if (sqlite3_changes(db_) == 0)
    return false;
  queueForHub(kOutboxDelete, id, ts);
  t.commit();
  return true;
}

bool Catalog::restoreItem(std::int64_t id) {
  Transaction t(db_);
  const std::string ts = now();
  Statement(
      *this,
      "UPDATE items SET deleted_at = NULL, updated_at = ? WHERE id = ? AND deleted_at IS NOT NULL")
      .bind(1, ts)
      .bind(2, id)
      .run();
  if (sqlite3_changes(db_) == 0)
    return false;
  queueForHub(kOutboxUpsert, id, ts);
  t.commit();
  return true;
}

// --- outbox (docs/hub.md) --------------------------------------------------------------------

// Inside the caller's transaction: the change and its outbox row commit or roll back together.
void Catalog::queueForHub(const char* kind, std::int64_t itemId, const std::string& ts) {
  Statement(*this, "INSERT INTO outbox(kind, item_id, created_at) VALUES(?,?,?)")
      .bind(1, kind)
      .bind(2, itemId)
      .bind(3, ts)
      .run();
}

std::vector<OutboxEntry> Catalog::outbox(int limit) {
  Statement s(*this, "SELECT seq, kind, item_id, created_at FROM outbox ORDER BY seq LIMIT ?");
  s.bind(1, std::clamp(limit, 1, 10000));
  std::vector<OutboxEntry> out;
  while (s.step())
    out.push_back({sqlite3_column_int64(s.get(), 0), text(s.get(), 1),
                   sqlite3_column_int64(s.get(), 2), text(s.get(), 3)});
  return out;
}

bool Catalog::removeOutbox(std::int64_t seq) {
  Statement(*this, "DELETE FROM outbox WHERE seq = ?").bind(1, seq).run();
  return sqlite3_changes(db_) > 0;
}

std::int64_t Catalog::outboxSize() {
  Statement s(*this, "SELECT count(*) FROM outbox");
  return s.step() ? sqlite3_column_int64(s.get(), 0) : 0;
}

bool Catalog::refuseOutbox(std::int64_t seq, int httpStatus, const std::string& reason) {
  Transaction t(db_);
  Statement(*this,
            "INSERT OR REPLACE INTO outbox_refused(seq, kind, item_id, created_at, http_status, "
            "reason, refused_at) SELECT seq, kind, item_id, created_at, ?, ?, ? FROM outbox "
            "WHERE seq = ?")
      .bind(1, static_cast<std::int64_t>(httpStatus))
      .bind(2, reason)
      .bind(3, isoUtc(std::chrono::system_clock::now()))
      .bind(4, seq)
      .run();
  if (sqlite3_changes(db_) == 0)
    return false;
  Statement(*this, "DELETE FROM outbox WHERE seq = ?").bind(1, seq).run();
  t.commit();
  return true;
}

std::vector<RefusedOutboxEntry> Catalog::refusedOutbox(int limit) {
  Statement s(*this,
              "SELECT seq, kind, item_id, created_at, http_status, reason, refused_at FROM "
              "outbox_refused ORDER BY seq DESC LIMIT ?");
  s.bind(1, std::clamp(limit, 1, 10000));
  std::vector<RefusedOutboxEntry> out;
  while (s.step()) {
    RefusedOutboxEntry e;
    e.row = {sqlite3_column_int64(s.get(), 0), text(s.get(), 1), sqlite3_column_int64(s.get(), 2),
             text(s.get(), 3)};
    e.httpStatus = sqlite3_column_int(s.get(), 4);
    e.reason = text(s.get(), 5);
    e.refusedAt = text(s.get(), 6);
    out.push_back(std::move(e));
  }
  return out;
}

std::int64_t Catalog::refusedOutboxSize() {
  Statement s(*this, "SELECT count(*) FROM outbox_refused");
  return s.step() ? sqlite3_column_int64(s.get(), 0) : 0;
}

std::optional<std::string> Catalog::hubState(const std::string& key) {
  Statement s(*this, "SELECT value FROM hub_state WHERE key = ?");
  s.bind(1, key);
  if (!s.step())
    return std::nullopt;
  return std::string(text(s.get(), 0));
}

void Catalog::setHubState(const std::string& key, const std::string& value) {
  Statement(*this, "INSERT OR REPLACE INTO hub_state(key, value) VALUES(?,?)")
      .bind(1, key)
      .bind(2, value)
      .run();
}

std::optional<nlohmann::json> Catalog::pattern(std::int64_t itemId, const std::string& size) {
  Statement s(*this, "SELECT json FROM patterns WHERE item_id = ? AND size = ?");
  s.bind(1, itemId).bind(2, size);
  if (!s.step())
    return std::nullopt;
  return jsonColumn(s.get(), 0, nullptr);
}

std::optional<nlohmann::json> Catalog::sizeGuide(std::int64_t itemId) {
  Statement s(*this, "SELECT size_guide FROM items WHERE id = ? AND deleted_at IS NULL");
  s.bind(1, itemId);
  if (!s.step())
    return std::nullopt;
  auto j = jsonColumn(s.get(), 0, nullptr);
  if (j.is_null())
    return std::nullopt;
  return j;
}

std::optional<nlohmann::json> Catalog::result(std::int64_t itemId) {
  Statement s(*this, "SELECT result FROM items WHERE id = ? AND deleted_at IS NULL");
  s.bind(1, itemId);
  if (!s.step())
    return std::nullopt;
  auto j = jsonColumn(s.get(), 0, nullptr);
  if (j.is_null())
    return std::nullopt;
  return j;
}

}  // namespace garmcap::daemon
