// The hub's store on a real PostgreSQL (temp_postgres.h): migrations, idempotent pushes by
// (station, local id), blobs, keyset listing, and each case of the ownership rule.
#include "garmcap/hub/hub_store.h"

#include <gtest/gtest.h>

#include <atomic>
#include <set>
#include <sstream>
#include <vector>

#include "garmcap/daemon/content_store.h"
#include "garmcap/hub/hub_config.h"
#include "temp_postgres.h"

namespace garmcap::hub {
namespace {

class HubStoreTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!test::postgresBinDir())
      return;
    pg_ = new test::TempPostgres();
  }
  static void TearDownTestSuite() {
    delete pg_;
    pg_ = nullptr;
  }
  void SetUp() override {
    if (!pg_)
      GTEST_SKIP() << "PostgreSQL server binaries not found under /usr/lib/postgresql "
                      "(apt install postgresql-15; ./station.sh deps installs it)";
    static std::atomic<int> n{0};
    db_ = "hub_" + std::to_string(n++);
    pg_->createDatabase(db_);
    store_ = std::make_unique<HubStore>(pg_->url(db_), 2);
    store_->setStations({{"shop1", tokenHash("t1")}, {"shop2", tokenHash("t2")}});
  }

  std::string blob(const std::string& bytes) {
    const auto sha = daemon::sha256Hex(bytes);
    store_->putBlob(sha, bytes);
    return sha;
  }
  PushedItem pushed(std::int64_t localId, const std::string& title, const std::string& status,
                    std::vector<PushedImage> images = {}) {
    PushedItem p;
    p.localId = localId;
    p.sku = "SKU-" + std::to_string(localId);
    p.title = title;
    p.status = status;
    p.type = "skirt";
    p.measurementsCm = {{"waist_circ", 70.5}};
    p.images = std::move(images);
    p.doc = {{"id", localId}, {"title", title}};
    return p;
  }

  static test::TempPostgres* pg_;
  std::string db_;
  std::unique_ptr<HubStore> store_;
};
test::TempPostgres* HubStoreTest::pg_ = nullptr;

TEST_F(HubStoreTest, MigratesOnceAndRefusesANewerSchema) {
  EXPECT_EQ(store_->schemaVersion(), kHubSchemaVersion);
  store_.reset();
  HubStore again(pg_->url(db_));  // reopening migrates nothing
  EXPECT_EQ(pg_->psql(db_, "SELECT count(*) FROM schema_migrations"),
            std::to_string(kHubSchemaVersion));
  pg_->psql(db_, "INSERT INTO schema_migrations(version) VALUES (99)");
  EXPECT_THROW(HubStore(pg_->url(db_)), HubStoreError);
}

TEST_F(HubStoreTest, PushIsIdempotentPerStationAndLocalId) {
  const auto sha = blob("dressed-frame");
  const auto a = store_->push(
      "shop1", pushed(7, "Red skirt", "needs_review", {{"dressed", sha, "image/png"}}));
  EXPECT_TRUE(a.created);
  const auto again = store_->push(
      "shop1", pushed(7, "Red skirt", "needs_review", {{"dressed", sha, "image/png"}}));
  EXPECT_FALSE(again.created);
  EXPECT_EQ(again.hubId, a.hubId);
  // The same local id at another station is another item.
  const auto b = store_->push("shop2", pushed(7, "Blue skirt", "needs_review"));
  EXPECT_NE(b.hubId, a.hubId);
  EXPECT_EQ(pg_->psql(db_, "SELECT count(*) FROM items"), "2");
  const auto it = store_->item(a.hubId);
  ASSERT_TRUE(it);
  EXPECT_EQ(it->station, "shop1");
  EXPECT_EQ(it->localId, 7);
  EXPECT_EQ(it->measurementsCm.at("waist_circ"), 70.5);
  ASSERT_EQ(it->images.size(), 1u);
  EXPECT_EQ(it->images[0].sha256, sha);
  EXPECT_EQ(it->doc["title"], "Red skirt");
  // An unknown station cannot push (its row is the lock the writes take).
  EXPECT_THROW(store_->push("shop9", pushed(1, "x", "needs_review")), HubStoreError);
}

TEST_F(HubStoreTest, BlobsRoundTripByteExactAndPushNeedsThem) {
  std::string bytes(300000, '\0');
  for (std::size_t i = 0; i < bytes.size(); ++i)
    bytes[i] = static_cast<char>((i * 131) & 0xff);
  const auto sha = daemon::sha256Hex(bytes);
  EXPECT_FALSE(store_->hasBlob(sha));
  store_->putBlob(sha, bytes);
  store_->putBlob(sha, bytes);  // idempotent
  EXPECT_TRUE(store_->hasBlob(sha));
  const auto back = store_->blob(sha);
  ASSERT_TRUE(back);
  EXPECT_EQ(daemon::sha256Hex(*back), sha);
  // PostgreSQL's own digest of the stored bytes agrees (pgcrypto-free: sha256() is built in).
  EXPECT_EQ(pg_->psql(db_, "SELECT encode(sha256(bytes), 'hex') FROM images"), sha);
  const std::string missing(64, 'e');
  try {
    store_->push("shop1", pushed(1, "t", "needs_review", {{"dressed", missing, "image/png"}}));
    FAIL() << "a push naming a missing blob must be refused";
  } catch (const HubStoreError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  EXPECT_EQ(pg_->psql(db_, "SELECT count(*) FROM items"), "0");
}

TEST_F(HubStoreTest, StationOwnsEveryFieldUntilApproval) {
  const auto id = store_->push("shop1", pushed(1, "first", "needs_review")).hubId;
  // The station renames: taken.
  EXPECT_FALSE(store_->push("shop1", pushed(1, "second", "needs_review")).hubKept);
  EXPECT_EQ(store_->item(id)->title, "second");
  // The hub may not edit a field of an item the station owns...
  HubPatch rename;
  rename.title = "hub title";
  EXPECT_EQ(store_->patch(id, rename), PatchResult::kStationOwned);
  HubPatch reject;
  reject.status = "rejected";
  EXPECT_EQ(store_->patch(id, reject), PatchResult::kStationOwned);
  EXPECT_EQ(store_->item(id)->title, "second");
  EXPECT_TRUE(store_->changes("shop1", 0, 100).empty());
  EXPECT_EQ(store_->patch(999999, rename), PatchResult::kNotFound);
}

TEST_F(HubStoreTest, ApprovalAtTheHubTakesOwnershipAndTellsTheStation) {
  const auto id = store_->push("shop1", pushed(3, "station title", "needs_review")).hubId;
  HubPatch approve;
  approve.status = "approved";
  approve.title = "Hub title";
  approve.priceCents = std::optional<std::int64_t>(5900);
  ASSERT_EQ(store_->patch(id, approve), PatchResult::kOk);
  auto it = store_->item(id);
  EXPECT_TRUE(it->hubOwned);
  EXPECT_EQ(it->title, "Hub title");
  EXPECT_EQ(it->priceCents, 5900);
  const auto ch = store_->changes("shop1", 0, 100);
  ASSERT_EQ(ch.size(), 1u);
  EXPECT_EQ(ch[0].localId, 3);
  EXPECT_EQ(ch[0].title, "Hub title");
  EXPECT_EQ(ch[0].status, "approved");
  EXPECT_EQ(ch[0].priceCents, 5900);
  EXPECT_TRUE(store_->changes("shop2", 0, 100).empty());  // only the item's station
  EXPECT_TRUE(store_->changes("shop1", ch[0].seq, 100).empty());
  // A later push from the station (it had not seen the change yet) keeps the hub's values and
  // queues them again; the station's other fields are still the station's.
  auto stale = pushed(3, "station title", "needs_review");
  stale.sku = "NEW-SKU";
  stale.measurementsCm = {{"waist_circ", 71.0}};
  EXPECT_TRUE(store_->push("shop1", stale).hubKept);
  it = store_->item(id);
  EXPECT_EQ(it->title, "Hub title");
  EXPECT_EQ(it->status, "approved");
  EXPECT_EQ(it->priceCents, 5900);
  EXPECT_EQ(it->sku, "NEW-SKU");
  EXPECT_EQ(it->measurementsCm.at("waist_circ"), 71.0);
  const auto again = store_->changes("shop1", ch[0].seq, 100);
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0].title, "Hub title");
  // Once the station agrees, a push queues nothing more.
  auto agreed = pushed(3, "Hub title", "approved");
  agreed.priceCents = 5900;
  store_->push("shop1", agreed);
  EXPECT_TRUE(store_->changes("shop1", again[0].seq, 100).empty());
  // Owned by the hub, the hub may also reject it later.
  HubPatch reject;
  reject.status = "rejected";
  EXPECT_EQ(store_->patch(id, reject), PatchResult::kOk);
  EXPECT_EQ(store_->item(id)->status, "rejected");
}

TEST_F(HubStoreTest, ApprovalAtTheStationHandsOwnershipToTheHub) {
  const auto id = store_->push("shop1", pushed(4, "approved at the shop", "approved")).hubId;
  EXPECT_TRUE(store_->item(id)->hubOwned);
  // The approving push itself was the station's: its title stands.
  EXPECT_EQ(store_->item(id)->title, "approved at the shop");
  // After it the station's title edits do not overwrite the hub's.
  EXPECT_TRUE(store_->push("shop1", pushed(4, "renamed at the shop", "approved")).hubKept);
  EXPECT_EQ(store_->item(id)->title, "approved at the shop");
  ASSERT_EQ(store_->changes("shop1", 0, 10).size(), 1u);
  // The hub edits it directly.
  HubPatch price;
  price.priceCents = std::optional<std::int64_t>(1200);
  EXPECT_EQ(store_->patch(id, price), PatchResult::kOk);
  EXPECT_EQ(store_->item(id)->priceCents, 1200);
  // Deleting stays the station's: the item leaves the list.
  auto gone = pushed(4, "approved at the shop", "approved");
  gone.deleted = true;
  store_->push("shop1", gone);
  EXPECT_TRUE(store_->item(id)->deletedAt);
  EXPECT_TRUE(store_->list({}).items.empty());
  EXPECT_EQ(store_->patch(id, price), PatchResult::kNotFound);
  gone.deleted = false;  // restored at the station
  store_->push("shop1", gone);
  EXPECT_FALSE(store_->item(id)->deletedAt);
}

TEST_F(HubStoreTest, KeysetPagesCoverEveryItemOnceWithFilters) {
  std::set<std::int64_t> expected;
  for (int i = 1; i <= 23; ++i)
    expected.insert(store_
                        ->push(i % 2 ? "shop1" : "shop2",
                               pushed(i, "Skirt " + std::to_string(i), "needs_review"))
                        .hubId);
  std::set<std::int64_t> seen;
  HubQuery q;
  q.limit = 5;
  std::int64_t last = std::numeric_limits<std::int64_t>::max();
  for (int pages = 0; pages < 10; ++pages) {
    const auto page = store_->list(q);
    for (const auto& it : page.items) {
      EXPECT_LT(it.id, last);  // newest first, no repeats
      last = it.id;
      EXPECT_TRUE(seen.insert(it.id).second);
    }
    if (!page.next)
      break;
    q.afterId = *page.next;
  }
  EXPECT_EQ(seen, expected);
  HubQuery station;
  station.station = "shop2";
  station.limit = 100;
  EXPECT_EQ(store_->list(station).items.size(), 11u);
  HubQuery search;
  search.search = "SKIRT 1";  // case-insensitive: 1, 10..19
  search.limit = 100;
  EXPECT_EQ(store_->list(search).items.size(), 11u);
  search.search = "%";  // a pattern character is matched as itself
  EXPECT_TRUE(store_->list(search).items.empty());
  // Both indexes exist for the planner to use.
  EXPECT_EQ(pg_->psql(db_,
                      "SELECT count(*) FROM pg_indexes WHERE indexname IN "
                      "('items_station_id', 'items_search')"),
            "2");
}

// The search finds its page in two steps (the newest rows first, then the trigram index's
// matches below them: hub_store.cpp, searchStatement). Against a plain substring test in C++ of
// every row psql reads back, for a term most items hold (found among the newest), one only old
// items hold (rare among the newest, common below them), rare ones, case, a station filter, deleted
// items, and pages small enough that every term crosses the newest-rows window.
TEST_F(HubStoreTest, SearchPagesEqualAFullScanForCommonRareAndOldTerms) {
  pg_->psql(db_, R"sql(
    INSERT INTO items(station_id, local_id, sku, title, status, type, deleted_at)
      SELECT 'shop' || (1 + g % 2), g, 'SKU-' || g,
             CASE WHEN g % 3 = 0 THEN 'Navy skirt ' ELSE 'Skirt ' END
             || CASE WHEN g <= 300 THEN 'Vintage ' ELSE '' END || md5(g::text),
             CASE WHEN g % 5 = 0 THEN 'approved' WHEN g % 7 = 0 THEN 'rejected'
                  ELSE 'needs_review' END, 'skirt', CASE WHEN g % 97 = 0 THEN now() END
      FROM generate_series(1, 3000) g;
    ANALYZE items;)sql");
  struct Row {
    std::int64_t id;
    std::string station, text;
    bool deleted;
    std::string status;
  };
  std::vector<Row> rows;  // newest first
  std::istringstream dump(pg_->psql(
      db_,
      "SELECT id, station_id, lower(sku || ' ' || title), deleted_at IS NOT NULL, status FROM "
      "items ORDER BY id DESC"));
  for (std::string line; std::getline(dump, line);) {
    std::vector<std::string> f;
    std::istringstream fields(line);
    for (std::string x; std::getline(fields, x, '|');)
      f.push_back(x);
    ASSERT_EQ(f.size(), 5u) << line;
    rows.push_back({std::stoll(f[0]), f[1], f[2], f[3] == "t", f[4]});
  }
  ASSERT_EQ(rows.size(), 3000u);
  const auto lower = [](std::string s) {
    for (char& ch : s)
      ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    return s;
  };
  struct Case {
    std::string term, station;
    int limit;
    std::string status;  // the status filter (the hub UI's), "" = any
  };
  // md5("7") starts 8f14e45f; "1e45" and "e45f" occur in a few titles only.
  const std::vector<Case> cases = {{"navy", "", 50, ""},
                                   {"NAVY SKIRT", "shop2", 7, ""},
                                   {"vintage", "", 50, ""},
                                   {"Vintage", "shop1", 7, ""},
                                   {"vintage", "", 500, ""},
                                   {"e45f", "", 3, ""},
                                   {"1e45", "shop2", 50, ""},
                                   {"SKU-29", "", 4, ""},
                                   {"skirt", "", 500, ""},
                                   {"no such thing", "", 50, ""},
                                   // The status filter, with and without a search term.
                                   {"navy", "", 50, "approved"},
                                   {"Vintage", "shop1", 7, "rejected"},
                                   {"navy", "shop2", 3, "needs_review"},
                                   {"skirt", "", 500, "approved"},
                                   {"", "shop2", 50, "rejected"},
                                   {"", "", 500, "approved"}};
  for (const auto& c : cases) {
    std::vector<std::int64_t> expected;
    for (const auto& r : rows)
      if (!r.deleted && (c.station.empty() || r.station == c.station) &&
          (c.status.empty() || r.status == c.status) &&
          r.text.find(lower(c.term)) != std::string::npos)
        expected.push_back(r.id);
    HubQuery q;
    q.search = c.term;
    q.station = c.station;
    q.status = c.status;
    q.limit = c.limit;
    std::vector<std::int64_t> got;
    for (int pages = 0; pages < 1000; ++pages) {
      const auto page = store_->list(q);
      EXPECT_LE(page.items.size(), static_cast<std::size_t>(c.limit));
      for (const auto& it : page.items)
        got.push_back(it.id);
      if (!page.next)
        break;
      EXPECT_EQ(page.items.size(), static_cast<std::size_t>(c.limit));
      EXPECT_EQ(*page.next, page.items.back().id);
      q.afterId = *page.next;
    }
    EXPECT_EQ(got, expected) << "q='" << c.term << "' station='" << c.station << "' status='"
                             << c.status << "' limit=" << c.limit;
    EXPECT_FALSE(expected.empty() && c.term != "no such thing") << c.term;
  }
}

TEST_F(HubStoreTest, ReconnectsAfterTheServerRestarts) {
  store_->push("shop1", pushed(1, "before", "needs_review"));
  pg_->stop();
  pg_->start();
  // The pooled connection is broken; the call is retried once on a fresh one.
  EXPECT_EQ(store_->push("shop1", pushed(2, "after", "needs_review")).created, true);
  EXPECT_EQ(store_->stationItems("shop1").size(), 2u);
}

}  // namespace
}  // namespace garmcap::hub
