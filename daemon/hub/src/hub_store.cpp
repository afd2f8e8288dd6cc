#include "garmcap/hub/hub_store.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <iterator>
#include <limits>
#include <pqxx/pqxx>

namespace garmcap::hub {

namespace {

// Version 1. Items are keyed by (station, local id); the list is newest first by id (keyset
// pagination on the primary key, per station on (station_id, id)); search is a trigram index on
// sku and title (pg_trgm is a trusted extension: the database owner may create it).
constexpr const char* kSchemaV1 = R"sql(
CREATE EXTENSION IF NOT EXISTS pg_trgm;
CREATE TABLE stations(
  id text PRIMARY KEY CHECK (id ~ '^[A-Za-z0-9_-]{1,64}$'),
  token_sha256 text NOT NULL CHECK (token_sha256 ~ '^[0-9a-f]{64}$'),
  created_at timestamptz NOT NULL DEFAULT now());
CREATE TABLE images(
  sha256 text PRIMARY KEY CHECK (sha256 ~ '^[0-9a-f]{64}$'),
  bytes bytea NOT NULL,
  size bigint NOT NULL,
  created_at timestamptz NOT NULL DEFAULT now());
CREATE TABLE items(
  id bigserial PRIMARY KEY,
  station_id text NOT NULL REFERENCES stations(id),
  local_id bigint NOT NULL CHECK (local_id > 0),
  sku text NOT NULL DEFAULT '',
  title text NOT NULL DEFAULT '',
  price_cents bigint,
  status text NOT NULL CHECK (status IN ('needs_review', 'approved', 'rejected')),
  type text NOT NULL DEFAULT '',
  hub_owned boolean NOT NULL DEFAULT false,
  doc jsonb NOT NULL DEFAULT '{}',
  created_at timestamptz NOT NULL DEFAULT now(),
  updated_at timestamptz NOT NULL DEFAULT now(),
  deleted_at timestamptz,
  UNIQUE (station_id, local_id));
CREATE INDEX items_station_id ON items(station_id, id);
CREATE INDEX items_search ON items USING gin ((sku || ' ' || title) gin_trgm_ops);
CREATE TABLE measurements(
  item_id bigint NOT NULL REFERENCES items(id) ON DELETE CASCADE,
  name text NOT NULL,
  value_cm double precision NOT NULL,
  PRIMARY KEY (item_id, name));
CREATE TABLE item_images(
  item_id bigint NOT NULL REFERENCES items(id) ON DELETE CASCADE,
  kind text NOT NULL,
  sha256 text NOT NULL REFERENCES images(sha256),
  media_type text NOT NULL,
  PRIMARY KEY (item_id, kind));
CREATE INDEX item_images_sha256 ON item_images(sha256);
CREATE TABLE hub_changes(
  seq bigserial PRIMARY KEY,
  station_id text NOT NULL REFERENCES stations(id),
  item_id bigint NOT NULL REFERENCES items(id),
  local_id bigint NOT NULL,
  title text NOT NULL,
  price_cents bigint,
  status text NOT NULL,
  created_at timestamptz NOT NULL DEFAULT now());
CREATE INDEX hub_changes_station ON hub_changes(station_id, seq);
)sql";

// Version 2: each item's patterns as the station drafted them (size -> the drafts library's
// pattern JSON), which the hub's pattern files and catalog.zip are written from.
constexpr const char* kSchemaV2 = R"sql(
CREATE TABLE item_patterns(
  item_id bigint NOT NULL REFERENCES items(id) ON DELETE CASCADE,
  size text NOT NULL CHECK (size ~ '^[A-Za-z0-9_-]{1,32}$'),
  pattern jsonb NOT NULL,
  PRIMARY KEY (item_id, size));
)sql";

// Version 3: the status filter's own indexes. The list with `status=` is `WHERE deleted_at IS
// NULL AND status = $s [AND station_id = $st] AND id < $after ORDER BY id DESC LIMIT n`; without
// them it walked the primary key (or items_station_id) newest first and skipped the rows of
// other statuses, so a page of a rare status read most of the table. Each index holds the live
// rows only (the list never shows deleted ones) in the list's order after its equalities, so a
// page is an index range read backwards from the cursor: (status, id) for the chain's list and
// the exports' approved pages (forwards), (station_id, status, id) for one station's.
constexpr const char* kSchemaV3 = R"sql(
CREATE INDEX items_status_id ON items(status, id) WHERE deleted_at IS NULL;
CREATE INDEX items_station_status_id ON items(station_id, status, id) WHERE deleted_at IS NULL;
)sql";

const std::vector<const char*>& migrations() {
  static const std::vector<const char*> kMigrations = {kSchemaV1, kSchemaV2, kSchemaV3};
  return kMigrations;
}

constexpr std::int64_t kMigrationLock = 0x47434150'48554221;  // "GCAPHUB!"

bool validStatus(const std::string& s) {
  return s == "needs_review" || s == "approved" || s == "rejected";
}

// ILIKE pattern for a substring, with the pattern characters of the input escaped.
std::string likePattern(const std::string& text) {
  std::string out = "%";
  for (char c : text) {
    if (c == '%' || c == '_' || c == '\\')
      out += '\\';
    out += c;
  }
  return out + "%";
}

std::optional<std::int64_t> optionalInt(const pqxx::field& f) {
  if (f.is_null())
    return std::nullopt;
  return f.as<std::int64_t>();
}

constexpr const char* kTime = "to_char(%s AT TIME ZONE 'UTC', 'YYYY-MM-DD\"T\"HH24:MI:SS.MS\"Z\"')";

std::string timeColumn(const char* column) {
  char buf[160];
  std::snprintf(buf, sizeof buf, kTime, column);
  return buf;
}

const std::string& itemColumns() {
  static const std::string kColumns =
      "SELECT id, station_id, local_id, sku, title, price_cents, status, type, hub_owned, "
      "doc::text, " +
      timeColumn("created_at") + ", " + timeColumn("updated_at") + ", " + timeColumn("deleted_at") +
      " FROM items ";
  return kColumns;
}

HubItem readItem(const pqxx::row& r) {
  HubItem it;
  it.id = r[0].as<std::int64_t>();
  it.station = r[1].c_str();
  it.localId = r[2].as<std::int64_t>();
  it.sku = r[3].c_str();
  it.title = r[4].c_str();
  it.priceCents = optionalInt(r[5]);
  it.status = r[6].c_str();
  it.type = r[7].c_str();
  it.hubOwned = r[8].as<bool>();
  it.doc = nlohmann::json::parse(r[9].c_str(), nullptr, false);
  if (it.doc.is_discarded())
    it.doc = nlohmann::json::object();
  it.createdAt = r[10].c_str();
  it.updatedAt = r[11].c_str();
  if (!r[12].is_null())
    it.deletedAt = std::string(r[12].c_str());
  return it;
}

void loadDetails(pqxx::transaction_base& w, HubItem& it) {
  for (const auto& r : w.exec_params(
           "SELECT name, value_cm FROM measurements WHERE item_id = $1 ORDER BY name", it.id))
    it.measurementsCm[r[0].c_str()] = r[1].as<double>();
  for (const auto& r : w.exec_params(
           "SELECT kind, sha256, media_type FROM item_images WHERE item_id = $1 ORDER BY kind",
           it.id))
    it.images.push_back({r[0].c_str(), r[1].c_str(), r[2].c_str()});
}

// The search's statement: the page's rows, newest first below $1 (station $2, ILIKE pattern $4,
// $5 rows, status $6), found in two steps, because no single plan is quick for every term. Ordered
// by id and limited, the planner either walks the primary key newest first and tests each row
// (quick for a term many items hold, a walk through the whole table for a rare one) or takes the
// trigram index's matches and sorts them (quick for a rare term, every matching row read for a
// common one); it picks by an estimate of the term's frequency that was off by a factor of 20
// to 30 for 4-letter terms, and a wrong pick cost 70 ms at 100,000 items (docs/hub.md, Scale).
//  1. `recent`: the newest rows below $1, a window of $3 = kSearchWindowPerRow rows per wanted
//     row, tested one by one. A term held by at least 1 in kSearchWindowPerRow items fills the
//     page here (`head`), at the cost of reading the window (about 2 ms for 2,000 rows).
//  2. Otherwise (the window was full and the page is not), the term is rare among the newest
//     items, and the rest of the page comes from `older`: the trigram index's matches, those
//     below the window and of the station taken, newest first. `older` is materialized with
//     the trigram condition alone: without an order the planner has no reason to walk the
//     primary key, and with no bound on id or station it does not AND the matches with a scan
//     of 98,000 primary-key or 33,000 station entries (it did, estimating either bound at a
//     third of the table: 8 to 30 ms). Its size is the number of items holding the term: small
//     for a rare term, large only for one rare among the newest items and common among the
//     older ones. A CTE is computed when first read, and the one-time filter keeps `older`
//     unread when the window answered.
constexpr int kSearchWindowPerRow = 40;

const std::string& searchStatement() {
  static const std::string kSql = itemColumns() + R"sql(
WHERE id IN (
  WITH recent AS MATERIALIZED (
    SELECT id, sku, title FROM items WHERE deleted_at IS NULL AND id < $1
      AND ($2 = '' OR station_id = $2) AND ($6 = '' OR status = $6) ORDER BY id DESC LIMIT $3),
  head AS MATERIALIZED (
    SELECT id FROM recent WHERE (sku || ' ' || title) ILIKE $4 ORDER BY id DESC LIMIT $5),
  older AS MATERIALIZED (
    SELECT id, station_id, status FROM items WHERE (sku || ' ' || title) ILIKE $4
      AND deleted_at IS NULL)
  SELECT id FROM head
  UNION ALL
  (SELECT id FROM older
     WHERE (SELECT count(*) FROM recent) = $3 AND (SELECT count(*) FROM head) < $5
       AND id < (SELECT min(id) FROM recent) AND ($2 = '' OR station_id = $2)
       AND ($6 = '' OR status = $6)
     ORDER BY id DESC LIMIT $5))
ORDER BY id DESC LIMIT $5)sql";
  return kSql;
}

// The details of a page of items in two queries, not two per item.
void loadDetails(pqxx::transaction_base& w, std::vector<HubItem>& items) {
  if (items.empty())
    return;
  std::map<std::int64_t, HubItem*> byId;
  std::string ids = "{";
  for (auto& it : items) {
    byId[it.id] = &it;
    ids += (ids.size() > 1 ? "," : "") + std::to_string(it.id);
  }
  ids += "}";
  for (const auto& r : w.exec_params("SELECT item_id, name, value_cm FROM measurements WHERE "
                                     "item_id = ANY($1::bigint[]) ORDER BY item_id, name",
                                     ids))
    byId.at(r[0].as<std::int64_t>())->measurementsCm[r[1].c_str()] = r[2].as<double>();
  for (const auto& r :
       w.exec_params("SELECT item_id, kind, sha256, media_type FROM item_images WHERE "
                     "item_id = ANY($1::bigint[]) ORDER BY item_id, kind",
                     ids))
    byId.at(r[0].as<std::int64_t>())->images.push_back({r[1].c_str(), r[2].c_str(), r[3].c_str()});
}

// The patterns of a page of items in one query.
void loadPatterns(pqxx::transaction_base& w, std::vector<HubItem>& items) {
  if (items.empty())
    return;
  std::map<std::int64_t, HubItem*> byId;
  std::string ids = "{";
  for (auto& it : items) {
    byId[it.id] = &it;
    ids += (ids.size() > 1 ? "," : "") + std::to_string(it.id);
  }
  ids += "}";
  for (const auto& r :
       w.exec_params("SELECT item_id, size, pattern::text FROM item_patterns WHERE item_id = "
                     "ANY($1::bigint[])",
                     ids))
    byId.at(r[0].as<std::int64_t>())->patterns[r[1].c_str()] = nlohmann::json::parse(r[2].c_str());
}

// Serializes the writes of one station's items and changes: the change rows of a station then
// commit in the order of their sequence numbers, so a reader's cursor never skips one that an
// earlier transaction was still about to commit.
void lockStation(pqxx::work& w, const std::string& station) {
  if (w.exec_params("SELECT 1 FROM stations WHERE id = $1 FOR UPDATE", station).empty())
    throw HubStoreError("unknown station '" + station + "'");
}

void queueChange(pqxx::work& w, std::int64_t itemId) {
  w.exec_params(
      "INSERT INTO hub_changes(station_id, item_id, local_id, title, price_cents, status) "
      "SELECT station_id, id, local_id, title, price_cents, status FROM items WHERE id = $1",
      itemId);
}

}  // namespace

nlohmann::json HubItem::toJson() const {
  nlohmann::json images = nlohmann::json::object();
  for (const auto& im : this->images)
    images[im.kind] = {{"sha256", im.sha256},
                       {"media_type", im.mediaType},
                       {"url", "/api/hub/blobs/" + im.sha256}};
  nlohmann::json j{{"id", id},
                   {"station", station},
                   {"local_id", localId},
                   {"sku", sku},
                   {"title", title},
                   {"status", status},
                   {"type", type},
                   {"hub_owned", hubOwned},
                   {"measurements", measurementsCm},
                   {"images", images},
                   {"station_item", doc},
                   {"pattern_sizes", patternSizes},
                   {"created_at", createdAt},
                   {"updated_at", updatedAt}};
  j["price_cents"] = priceCents ? nlohmann::json(*priceCents) : nlohmann::json(nullptr);
  j["deleted_at"] = deletedAt ? nlohmann::json(*deletedAt) : nlohmann::json(nullptr);
  return j;
}

nlohmann::json HubChange::toJson() const {
  nlohmann::json j{{"seq", seq}, {"local_id", localId}, {"title", title}, {"status", status}};
  j["price_cents"] = priceCents ? nlohmann::json(*priceCents) : nlohmann::json(nullptr);
  return j;
}

struct HubStore::Connection {
  explicit Connection(const std::string& cs) : c(cs) {}
  pqxx::connection c;
};

HubStore::HubStore(std::string connectionString, int connections)
    : connectionString_(std::move(connectionString)), capacity_(std::max(1, connections)) {
  migrate();
}

HubStore::~HubStore() = default;

std::unique_ptr<HubStore::Connection> HubStore::acquire() {
  {
    std::unique_lock lock(mutex_);
    available_.wait(lock, [&] { return !idle_.empty() || open_ < capacity_; });
    if (!idle_.empty()) {
      auto c = std::move(idle_.back());
      idle_.pop_back();
      return c;
    }
    ++open_;
  }
  try {
    return std::make_unique<Connection>(connectionString_);
  } catch (...) {
    std::lock_guard lock(mutex_);
    --open_;
    available_.notify_one();
    throw;
  }
}

void HubStore::release(std::unique_ptr<Connection> c, bool healthy) {
  std::lock_guard lock(mutex_);
  if (healthy && c && c->c.is_open())
    idle_.push_back(std::move(c));
  else
    --open_;
  available_.notify_one();
}

template <typename Fn>
auto HubStore::withConnection(Fn&& fn) {
  for (int attempt = 0;; ++attempt) {
    auto c = acquire();
    try {
      if constexpr (std::is_void_v<decltype(fn(c->c))>) {
        fn(c->c);
        release(std::move(c), true);
        return;
      } else {
        auto result = fn(c->c);
        release(std::move(c), true);
        return result;
      }
    } catch (const pqxx::broken_connection& e) {
      release(std::move(c), false);
      if (attempt > 0)
        throw;
      spdlog::warn("hub: database connection lost ({}); reconnecting", e.what());
    } catch (...) {
      release(std::move(c), true);
      throw;
    }
  }
}

void HubStore::migrate() {
  withConnection([](pqxx::connection& c) {
    pqxx::work w(c);
    w.exec_params("SELECT pg_advisory_xact_lock($1)", kMigrationLock);
    w.exec(
        "CREATE TABLE IF NOT EXISTS schema_migrations(version integer PRIMARY KEY, "
        "applied_at timestamptz NOT NULL DEFAULT now())");
    const auto r = w.exec("SELECT coalesce(max(version), 0) FROM schema_migrations");
    int version = r[0][0].as<int>();
    if (version > kHubSchemaVersion)
      throw HubStoreError("hub database: schema version " + std::to_string(version) +
                          " is newer than this garmcap-hub (" + std::to_string(kHubSchemaVersion) +
                          "); refusing to use it");
    // One transaction for the lock and every step: a failed step leaves the schema as it was.
    while (version < kHubSchemaVersion) {
      spdlog::info("hub: migrating the database from schema {} to {}", version, version + 1);
      w.exec(migrations()[static_cast<std::size_t>(version)]);
      w.exec_params("INSERT INTO schema_migrations(version) VALUES($1)", version + 1);
      ++version;
    }
    w.commit();
  });
}

int HubStore::schemaVersion() {
  return withConnection([](pqxx::connection& c) {
    pqxx::work w(c);
    return w.exec("SELECT coalesce(max(version), 0) FROM schema_migrations")[0][0].as<int>();
  });
}

void HubStore::setStations(const std::map<std::string, std::string>& tokens) {
  withConnection([&](pqxx::connection& c) {
    pqxx::work w(c);
    // Rows that are already right are not written: a start must not wait for the row lock
    // that pushes of that station hold.
    std::map<std::string, std::string> known;
    for (const auto& r : w.exec("SELECT id, token_sha256 FROM stations"))
      known[r[0].c_str()] = r[1].c_str();
    for (const auto& [station, hash] : tokens) {
      auto it = known.find(station);
      if (it == known.end())
        w.exec_params(
            "INSERT INTO stations(id, token_sha256) VALUES($1, $2) ON CONFLICT (id) DO NOTHING",
            station, hash);
      else if (it->second != hash)
        w.exec_params("UPDATE stations SET token_sha256 = $2 WHERE id = $1", station, hash);
    }
    w.commit();
  });
  std::lock_guard lock(tokensMutex_);
  stationByToken_.clear();
  for (const auto& [station, hash] : tokens)
    stationByToken_[hash] = station;
}

std::optional<std::string> HubStore::stationForToken(const std::string& tokenSha256) {
  std::lock_guard lock(tokensMutex_);
  auto it = stationByToken_.find(tokenSha256);
  if (it == stationByToken_.end())
    return std::nullopt;
  return it->second;
}

bool HubStore::hasBlob(const std::string& sha256) {
  return withConnection([&](pqxx::connection& c) {
    pqxx::work w(c);
    return !w.exec_params("SELECT 1 FROM images WHERE sha256 = $1", sha256).empty();
  });
}

void HubStore::putBlob(const std::string& sha256, const std::string& bytes) {
  withConnection([&](pqxx::connection& c) {
    pqxx::work w(c);
    w.exec_params(
        "INSERT INTO images(sha256, bytes, size) VALUES($1, $2, $3) ON CONFLICT (sha256) DO "
        "NOTHING",
        sha256, pqxx::binarystring(bytes.data(), bytes.size()),
        static_cast<std::int64_t>(bytes.size()));
    w.commit();
  });
}

std::optional<std::string> HubStore::blob(const std::string& sha256) {
  return withConnection([&](pqxx::connection& c) -> std::optional<std::string> {
    pqxx::work w(c);
    const auto r = w.exec_params("SELECT bytes FROM images WHERE sha256 = $1", sha256);
    if (r.empty())
      return std::nullopt;
    return pqxx::binarystring(r[0][0]).str();
  });
}

bool HubStore::blobOfStation(const std::string& sha256, const std::string& station) {
  return withConnection([&](pqxx::connection& c) {
    pqxx::work w(c);
    return !w.exec_params(
                 "SELECT 1 FROM item_images ii JOIN items i ON i.id = ii.item_id WHERE "
                 "ii.sha256 = $1 AND i.station_id = $2 LIMIT 1",
                 sha256, station)
                .empty();
  });
}

PushOutcome HubStore::push(const std::string& station, const PushedItem& in) {
  if (in.localId <= 0)
    throw HubStoreError("local_id must be a positive integer");
  if (!validStatus(in.status))
    throw HubStoreError("status must be needs_review, approved or rejected, got '" + in.status +
                        "'");
  return withConnection([&](pqxx::connection& c) {
    pqxx::work w(c);
    lockStation(w, station);
    for (const auto& im : in.images)
      if (w.exec_params("SELECT 1 FROM images WHERE sha256 = $1", im.sha256).empty())
        throw HubStoreError("image '" + im.kind + "' (" + im.sha256 +
                            ") is not at the hub: PUT /api/hub/blobs/" + im.sha256 + " first");
    const auto price = [&]() -> std::optional<std::string> {
      if (!in.priceCents)
        return std::nullopt;
      return std::to_string(*in.priceCents);
    }();
    const char* priceArg = price ? price->c_str() : nullptr;
    const std::string doc = in.doc.dump();
    PushOutcome out;
    const auto existing = w.exec_params(
        "SELECT id, hub_owned, title, price_cents, status FROM items WHERE station_id = $1 AND "
        "local_id = $2 FOR UPDATE",
        station, in.localId);
    if (existing.empty()) {
      out.created = true;
      out.hubId = w.exec_params(
                       "INSERT INTO items(station_id, local_id, sku, title, price_cents, status, "
                       "type, hub_owned, doc, deleted_at) VALUES($1, $2, $3, $4, $5::bigint, $6, "
                       "$7, $6 = 'approved', $8::jsonb, CASE WHEN $9 THEN now() END) RETURNING id",
                       station, in.localId, in.sku, in.title, priceArg, in.status, in.type, doc,
                       in.deleted)[0][0]
                      .as<std::int64_t>();
    } else {
      out.hubId = existing[0][0].as<std::int64_t>();
      if (!existing[0][1].as<bool>()) {
        // Station-owned: every field is the station's.
        w.exec_params(
            "UPDATE items SET sku = $2, title = $3, price_cents = $4::bigint, status = $5, "
            "type = $6, hub_owned = ($5 = 'approved'), doc = $7::jsonb, updated_at = now(), "
            "deleted_at = CASE WHEN $8 THEN coalesce(deleted_at, now()) END WHERE id = $1",
            out.hubId, in.sku, in.title, priceArg, in.status, in.type, doc, in.deleted);
      } else {
        // Hub-owned: title, price and status stay the hub's; the station is told if it differs.
        out.hubKept = true;
        w.exec_params(
            "UPDATE items SET sku = $2, type = $3, doc = $4::jsonb, updated_at = now(), "
            "deleted_at = CASE WHEN $5 THEN coalesce(deleted_at, now()) END WHERE id = $1",
            out.hubId, in.sku, in.type, doc, in.deleted);
        const std::string hubTitle = existing[0][2].c_str();
        const auto hubPrice = optionalInt(existing[0][3]);
        const std::string hubStatus = existing[0][4].c_str();
        if (hubTitle != in.title || hubPrice != in.priceCents || hubStatus != in.status)
          queueChange(w, out.hubId);
      }
      w.exec_params("DELETE FROM measurements WHERE item_id = $1", out.hubId);
      w.exec_params("DELETE FROM item_images WHERE item_id = $1", out.hubId);
    }
    for (const auto& [name, cm] : in.measurementsCm)
      w.exec_params("INSERT INTO measurements(item_id, name, value_cm) VALUES($1, $2, $3)",
                    out.hubId, name, cm);
    for (const auto& im : in.images)
      w.exec_params(
          "INSERT INTO item_images(item_id, kind, sha256, media_type) VALUES($1, $2, $3, $4)",
          out.hubId, im.kind, im.sha256, im.mediaType);
    if (in.patterns) {
      w.exec_params("DELETE FROM item_patterns WHERE item_id = $1", out.hubId);
      for (const auto& [size, pattern] : *in.patterns)
        w.exec_params("INSERT INTO item_patterns(item_id, size, pattern) VALUES($1, $2, $3::jsonb)",
                      out.hubId, size, pattern.dump());
    }
    w.commit();
    return out;
  });
}

std::vector<HubStation> HubStore::stations() {
  return withConnection([](pqxx::connection& c) {
    pqxx::work w(c);
    std::vector<HubStation> out;
    // One count per station and status; the (station_id, status, id) index of the live rows
    // (schema 3) answers it without reading the table's rows.
    for (const auto& r : w.exec("SELECT s.id, i.status, count(i.id) FROM stations s LEFT JOIN "
                                "items i ON i.station_id = s.id AND i.deleted_at IS NULL "
                                "GROUP BY s.id, i.status ORDER BY s.id")) {
      if (out.empty() || out.back().id != r[0].c_str())
        out.push_back({r[0].c_str(), 0, {}});
      if (r[1].is_null())
        continue;  // a station with no live item
      const auto n = r[2].as<std::int64_t>();
      out.back().items += n;
      out.back().byStatus[r[1].c_str()] = n;
    }
    return out;
  });
}

std::optional<HubItem> HubStore::item(std::int64_t id) {
  return withConnection([&](pqxx::connection& c) -> std::optional<HubItem> {
    pqxx::work w(c);
    const auto r = w.exec_params(itemColumns() + "WHERE id = $1", id);
    if (r.empty())
      return std::nullopt;
    HubItem it = readItem(r[0]);
    loadDetails(w, it);
    for (const auto& p :
         w.exec_params("SELECT size FROM item_patterns WHERE item_id = $1 ORDER BY size", id))
      it.patternSizes.push_back(p[0].c_str());
    return it;
  });
}

HubPage HubStore::list(const HubQuery& q) {
  const int limit = std::clamp(q.limit, 1, 500);
  // Fixed statements; an empty filter is disabled through its bound value. The keyset bound is
  // the largest bigint when starting, so one form of the query serves every page.
  const std::int64_t after = q.afterId > 0 ? q.afterId : std::numeric_limits<std::int64_t>::max();
  return withConnection([&](pqxx::connection& c) {
    pqxx::work w(c);
    const auto r =
        q.search.empty()
            ? w.exec_params(itemColumns() +
                                "WHERE deleted_at IS NULL AND id < $1 AND ($2 = '' OR "
                                "station_id = $2) AND ($4 = '' OR status = $4) "
                                "ORDER BY id DESC LIMIT $3",
                            after, q.station, limit + 1, q.status)
            : w.exec_params(searchStatement(), after, q.station, kSearchWindowPerRow * (limit + 1),
                            likePattern(q.search), limit + 1, q.status);
    HubPage page;
    for (const auto& row : r) {
      if (static_cast<int>(page.items.size()) == limit) {
        page.next = page.items.back().id;
        break;
      }
      page.items.push_back(readItem(row));
    }
    loadDetails(w, page.items);
    return page;
  });
}

std::vector<HubItem> HubStore::approvedItems(const std::string& station, bool withPatterns,
                                             std::size_t limit) {
  return withConnection([&](pqxx::connection& c) {
    pqxx::transaction<pqxx::repeatable_read, pqxx::read_only> w(c);
    std::vector<HubItem> out;
    // Pages of 1,000 on the primary key, each page's details in two queries.
    for (std::int64_t after = 0;;) {
      std::vector<HubItem> page;
      for (const auto& row :
           w.exec_params(itemColumns() + "WHERE status = 'approved' AND deleted_at IS NULL "
                                         "AND id > $1 AND ($2 = '' OR station_id = $2) "
                                         "ORDER BY id LIMIT 1000",
                         after, station))
        page.push_back(readItem(row));
      if (page.empty() || out.size() >= limit)
        return out;
      if (page.size() > limit - out.size())
        page.resize(limit - out.size());
      after = page.back().id;
      loadDetails(w, page);
      if (withPatterns)
        loadPatterns(w, page);
      std::move(page.begin(), page.end(), std::back_inserter(out));
    }
  });
}

namespace {

class PgApprovedReader : public ApprovedReader {
 public:
  PgApprovedReader(const std::string& connectionString, std::string station)
      : connection_(connectionString), tx_(connection_), station_(std::move(station)) {}
  std::vector<HubItem> next(int limit) override {
    std::vector<HubItem> page;
    for (const auto& row :
         tx_.exec_params(itemColumns() + "WHERE status = 'approved' AND deleted_at IS NULL "
                                         "AND id > $1 AND ($2 = '' OR station_id = $2) "
                                         "ORDER BY id LIMIT $3",
                         after_, station_, std::clamp(limit, 1, 10000)))
      page.push_back(readItem(row));
    if (!page.empty())
      after_ = page.back().id;
    loadDetails(tx_, page);
    return page;
  }
  void rewind() override { after_ = 0; }
  std::map<std::string, nlohmann::json> patterns(std::int64_t itemId) override {
    std::map<std::string, nlohmann::json> out;
    for (const auto& r : tx_.exec_params(
             "SELECT size, pattern::text FROM item_patterns WHERE item_id = $1", itemId))
      out[r[0].c_str()] = nlohmann::json::parse(r[1].c_str());
    return out;
  }
  std::optional<std::string> blob(const std::string& sha256) override {
    const auto r = tx_.exec_params("SELECT bytes FROM images WHERE sha256 = $1", sha256);
    if (r.empty())
      return std::nullopt;
    return pqxx::binarystring(r[0][0]).str();
  }

 private:
  pqxx::connection connection_;
  pqxx::transaction<pqxx::repeatable_read, pqxx::read_only> tx_;
  std::string station_;
  std::int64_t after_ = 0;
};

}  // namespace

std::unique_ptr<ApprovedReader> HubStore::readApproved(const std::string& station) {
  return std::make_unique<PgApprovedReader>(connectionString_, station);
}

std::optional<nlohmann::json> HubStore::pattern(std::int64_t itemId, const std::string& size) {
  return withConnection([&](pqxx::connection& c) -> std::optional<nlohmann::json> {
    pqxx::work w(c);
    const auto r = w.exec_params(
        "SELECT pattern::text FROM item_patterns WHERE item_id = $1 AND size = $2", itemId, size);
    if (r.empty())
      return std::nullopt;
    return nlohmann::json::parse(r[0][0].c_str());
  });
}

std::map<std::string, nlohmann::json> HubStore::patterns(std::int64_t itemId) {
  return withConnection([&](pqxx::connection& c) {
    pqxx::work w(c);
    std::map<std::string, nlohmann::json> out;
    for (const auto& r :
         w.exec_params("SELECT size, pattern::text FROM item_patterns WHERE item_id = $1", itemId))
      out[r[0].c_str()] = nlohmann::json::parse(r[1].c_str());
    return out;
  });
}

PatchResult HubStore::patch(std::int64_t id, const HubPatch& p) {
  if (p.status && !validStatus(*p.status))
    throw HubStoreError("status must be needs_review, approved or rejected, got '" + *p.status +
                        "'");
  return withConnection([&](pqxx::connection& c) {
    pqxx::work w(c);
    const auto owner =
        w.exec_params("SELECT station_id FROM items WHERE id = $1 AND deleted_at IS NULL", id);
    if (owner.empty())
      return PatchResult::kNotFound;
    lockStation(w, owner[0][0].c_str());
    const auto r = w.exec_params(
        "SELECT hub_owned FROM items WHERE id = $1 AND deleted_at IS NULL FOR UPDATE", id);
    if (r.empty())
      return PatchResult::kNotFound;
    // Before approval the station owns every field: the hub may approve (and set title and
    // price with the approval), nothing else.
    if (!r[0][0].as<bool>() && p.status != std::optional<std::string>("approved"))
      return PatchResult::kStationOwned;
    if (p.title)
      w.exec_params("UPDATE items SET title = $2 WHERE id = $1", id, *p.title);
    if (p.priceCents) {
      if (*p.priceCents)
        w.exec_params("UPDATE items SET price_cents = $2 WHERE id = $1", id, **p.priceCents);
      else
        w.exec_params("UPDATE items SET price_cents = NULL WHERE id = $1", id);
    }
    if (p.status)
      w.exec_params("UPDATE items SET status = $2 WHERE id = $1", id, *p.status);
    w.exec_params("UPDATE items SET hub_owned = true, updated_at = now() WHERE id = $1", id);
    queueChange(w, id);
    w.commit();
    return PatchResult::kOk;
  });
}

std::vector<HubChange> HubStore::changes(const std::string& station, std::int64_t since,
                                         int limit) {
  return withConnection([&](pqxx::connection& c) {
    pqxx::work w(c);
    std::vector<HubChange> out;
    for (const auto& r :
         w.exec_params("SELECT seq, local_id, title, price_cents, status FROM hub_changes WHERE "
                       "station_id = $1 AND seq > $2 ORDER BY seq LIMIT $3",
                       station, since, std::clamp(limit, 1, 1000)))
      out.push_back({r[0].as<std::int64_t>(), r[1].as<std::int64_t>(), r[2].c_str(), r[4].c_str(),
                     optionalInt(r[3])});
    return out;
  });
}

std::map<std::int64_t, std::int64_t> HubStore::stationItems(const std::string& station) {
  return withConnection([&](pqxx::connection& c) {
    pqxx::work w(c);
    std::map<std::int64_t, std::int64_t> out;
    for (const auto& r :
         w.exec_params("SELECT local_id, id FROM items WHERE station_id = $1", station))
      out[r[0].as<std::int64_t>()] = r[1].as<std::int64_t>();
    return out;
  });
}

}  // namespace garmcap::hub
