#include "garmcap/daemon/catalog.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <sstream>
#include <thread>

#include "garmcap/daemon/content_store.h"
#include "test_util.h"

namespace garmcap::daemon {
namespace {

std::string sha(char c) {
  return std::string(64, c);
}

NewItem sampleItem(std::int64_t jobId, std::int64_t calId) {
  NewItem n;
  n.sku = "SKU-42";
  n.title = "Red dress";
  n.type = "dress";
  n.attributes = {{"sleeve", "short"}};
  n.confidence = 0.9;
  n.measurementsCm = {{"bust_circ", 88.5}, {"waist_circ", 70.0}};
  n.images = {{"dressed", sha('d'), "image/png", 100}, {"cutout", sha('c'), "image/png", 50}};
  n.patterns = {{"base", {{"type", "dress"}}}, {"55", {{"type", "dress"}, {"size", "55"}}}};
  n.baseSize = "55";
  n.sizeGuide = {{"units", "cm"},
                 {"sizes", {"44", "55"}},
                 {"measurements", {{"bust_circ", {{"44", 82.0}, {"55", 88.0}}}}}};
  n.result = {{"type", "dress"}};
  n.calibrationId = calId;
  n.jobId = jobId;
  n.needsReview = false;
  return n;
}

TEST(Catalog, CreatesCurrentSchemaWithPragmas) {
  test::TempDir dir;
  Catalog c(dir.path() / "c.sqlite");
  EXPECT_EQ(c.schemaVersion(), kCatalogSchemaVersion);
  EXPECT_EQ(c.integrityCheck(), "ok");
  sqlite3_stmt* s = nullptr;
  sqlite3_prepare_v2(c.handle(), "PRAGMA journal_mode", -1, &s, nullptr);
  ASSERT_EQ(sqlite3_step(s), SQLITE_ROW);
  EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(s, 0)), "wal");
  sqlite3_finalize(s);
  sqlite3_prepare_v2(c.handle(), "PRAGMA foreign_keys", -1, &s, nullptr);
  ASSERT_EQ(sqlite3_step(s), SQLITE_ROW);
  EXPECT_EQ(sqlite3_column_int(s, 0), 1);
  sqlite3_finalize(s);
  sqlite3_prepare_v2(c.handle(), "PRAGMA synchronous", -1, &s, nullptr);
  ASSERT_EQ(sqlite3_step(s), SQLITE_ROW);
  EXPECT_EQ(sqlite3_column_int(s, 0), 2);  // FULL
  sqlite3_finalize(s);
}

TEST(Catalog, ItemRoundTripEditDeleteRestore) {
  test::TempDir dir;
  Catalog c(dir.path() / "c.sqlite");
  c.addImage(sha('e'), "image/png", 10);
  const auto cal = c.addCalibration(sha('e'), {{"scale", 1}});
  const auto job = c.addJob("dressed", "SKU-42");
  const auto id = c.addItem(sampleItem(job, cal));
  auto item = c.item(id);
  ASSERT_TRUE(item);
  EXPECT_EQ(item->sku, "SKU-42");
  EXPECT_EQ(item->status, kStatusApproved);
  EXPECT_DOUBLE_EQ(item->measurementsCm.at("bust_circ"), 88.5);
  ASSERT_EQ(item->images.size(), 2u);
  ASSERT_EQ(item->sizes.size(), 2u);
  EXPECT_EQ(item->sizes[0], "base");
  EXPECT_EQ(item->calibrationId, cal);
  auto j = c.job(job);
  ASSERT_TRUE(j);
  EXPECT_EQ(j->state, "done");
  EXPECT_EQ(j->itemId, id);
  EXPECT_EQ(c.pattern(id, "55")->at("size"), "55");
  EXPECT_FALSE(c.pattern(id, "99"));
  EXPECT_EQ(c.sizeGuide(id)->at("sizes").size(), 2u);

  ItemPatch p;
  p.title = "Crimson dress";
  p.tags = std::vector<std::string>{"evening", "silk"};
  p.priceCents = std::optional<std::int64_t>(12900);
  p.measurementsCm = std::map<std::string, double>{{"waist_circ", 71.5}};
  ASSERT_TRUE(c.patchItem(id, p));
  item = c.item(id);
  EXPECT_EQ(item->title, "Crimson dress");
  EXPECT_EQ(item->tags.size(), 2u);
  EXPECT_EQ(item->priceCents, 12900);
  EXPECT_DOUBLE_EQ(item->measurementsCm.at("waist_circ"), 71.5);
  EXPECT_DOUBLE_EQ(item->measurementsCm.at("bust_circ"), 88.5);

  ItemPatch bad;
  bad.status = "sold";
  EXPECT_THROW(c.patchItem(id, bad), CatalogError);
  EXPECT_FALSE(c.patchItem(id + 100, p));

  EXPECT_TRUE(c.deleteItem(id));
  EXPECT_FALSE(c.item(id));
  EXPECT_TRUE(c.item(id, true));
  EXPECT_FALSE(c.deleteItem(id));
  ItemQuery bin;
  bin.deleted = true;
  EXPECT_EQ(c.items(bin).second, 1);
  EXPECT_TRUE(c.restoreItem(id));
  EXPECT_TRUE(c.item(id));
  EXPECT_FALSE(c.restoreItem(id));
}

// Reclaiming storage (docs/daemon.md, "Storage"): a blob goes only when no row names it.
// A calibration on bare frame 'e' and a capture job whose dressed frame 'd' is stored.
std::pair<std::int64_t, std::int64_t> calibrateAndCapture(Catalog& c) {
  c.addImage(sha('e'), "image/png", 10);
  const auto cal = c.addCalibration(sha('e'), {{"scale", 1}});
  const auto job = c.addJob("dressed", "SKU-42");
  c.addImage(sha('d'), "image/png", 100);
  c.setJobFrames(job, sha('e'), sha('d'));
  return {cal, job};
}

TEST(CatalogStorage, ReRunReleasesOnlyTheImagesNothingElseNames) {
  test::TempDir dir;
  Catalog c(dir.path() / "c.sqlite");
  const auto [cal, job] = calibrateAndCapture(c);
  NewItem first = sampleItem(job, cal);
  first.images.push_back({"texture", sha('t'), "image/png", 20});
  const auto id = c.addItem(first);
  // A second item shares the cutout (the same garment replayed gives the same bytes).
  const auto other = c.addItem(sampleItem(c.addJob("dressed", "SKU-43"), cal));

  NewItem again = sampleItem(job, cal);
  again.images = {{"dressed", sha('d'), "image/png", 100}, {"cutout", sha('1'), "image/png", 60}};
  auto previous = c.replaceItemResults(id, again);
  std::sort(previous.begin(), previous.end());
  EXPECT_EQ(previous, (std::vector<std::string>{sha('c'), sha('d'), sha('t')}));
  // The texture the re-run no longer makes is not shown any more.
  ASSERT_EQ(c.item(id)->images.size(), 2u);

  // Only the texture goes: the old cutout is still the other item's, the dressed frame the job's.
  EXPECT_EQ(c.dropUnreferencedImages(previous), std::vector<std::string>{sha('t')});
  EXPECT_EQ(c.referencedImages().count(sha('t')), 0u);
  EXPECT_EQ(c.referencedImages().count(sha('c')), 1u);
  EXPECT_TRUE(c.dropUnreferencedImages(previous).empty());  // idempotent
  EXPECT_TRUE(c.dropUnreferencedImages().empty());          // the full scan agrees
  ASSERT_TRUE(c.item(other));
  EXPECT_EQ(c.integrityCheck(), "ok");
}

// The back shot (issue 17) adds images to a filed item and nothing else; a second back shot
// replaces the first one's kinds, including one it no longer makes.
TEST(CatalogStorage, BackShotAddsImagesLeavesResultsAndReplacesItsOwnKinds) {
  test::TempDir dir;
  Catalog c(dir.path() / "c.sqlite");
  const auto [cal, job] = calibrateAndCapture(c);
  const auto id = c.addItem(sampleItem(job, cal));
  const Item before = *c.item(id);
  const std::int64_t outboxBefore = c.outboxSize();
  const std::vector<std::string> kinds = {"back", "product_back", "product_ghost"};

  const auto backJob = c.addJob("back", "", id);
  c.addImage(sha('b'), "image/png", 100);
  c.setJobFrames(backJob, sha('e'), sha('b'));  // the station records the still first
  EXPECT_TRUE(c.addItemImages(id, kinds,
                              {{"back", sha('b'), "image/png", 100},
                               {"product_back", sha('p'), "image/jpeg", 30},
                               {"product_ghost", sha('g'), "image/jpeg", 30}},
                              backJob, cal)
                  .empty());
  const Item after = *c.item(id);
  EXPECT_EQ(after.images.size(), before.images.size() + 3);
  EXPECT_EQ(after.measurementsCm, before.measurementsCm);
  EXPECT_EQ(after.sizes, before.sizes);
  EXPECT_EQ(after.status, before.status);
  EXPECT_EQ(after.jobId, before.jobId);  // the item's capture job still names its dressed frame
  EXPECT_EQ(c.job(backJob)->state, "done");
  EXPECT_EQ(c.job(backJob)->itemId, id);
  EXPECT_EQ(c.job(backJob)->dressedSha256, "");  // the item names the still now
  EXPECT_EQ(c.outboxSize(), outboxBefore + 1);   // the hub gets the new photos

  // The second back shot made no ghost photo: the first one's is not left showing.
  auto replaced = c.addItemImages(
      id, kinds,
      {{"back", sha('B'), "image/png", 100}, {"product_back", sha('P'), "image/jpeg", 30}},
      c.addJob("back", "", id), cal);
  std::sort(replaced.begin(), replaced.end());
  EXPECT_EQ(replaced, (std::vector<std::string>{sha('b'), sha('g'), sha('p')}));
  const Item second = *c.item(id);
  EXPECT_EQ(second.images.size(), before.images.size() + 2);
  EXPECT_TRUE(std::none_of(second.images.begin(), second.images.end(),
                           [](const ImageRef& im) { return im.kind == "product_ghost"; }));
  EXPECT_EQ(c.dropUnreferencedImages(replaced).size(), 3u);

  ASSERT_TRUE(c.deleteItem(id));
  EXPECT_THROW(c.addItemImages(id, kinds, {{"back", sha('x'), "image/png", 1}}, std::nullopt, cal),
               CatalogError);
  EXPECT_EQ(c.integrityCheck(), "ok");
}

TEST(CatalogStorage, DeletedItemsArePurgedAfterTheirRetentionAndNotBeforeTheHubKnows) {
  test::TempDir dir;
  Catalog c(dir.path() / "c.sqlite");
  const auto [cal, job] = calibrateAndCapture(c);
  const auto id = c.addItem(sampleItem(job, cal));
  NewItem kept = sampleItem(c.addJob("dressed", "SKU-43"), cal);
  kept.images[0].sha256 = sha('2');  // its own frame, the same cutout
  const auto keep = c.addItem(kept);
  ASSERT_TRUE(c.deleteItem(id));
  const auto now = std::chrono::system_clock::now();

  // Deleted just now: a retention that started a day ago keeps it (it can still be restored).
  EXPECT_TRUE(c.purgeDeletedItems(now - std::chrono::hours(24), false).empty());
  EXPECT_TRUE(c.item(id, true));
  // With a hub, the deletion waits in the outbox: the item stays until it has been sent.
  EXPECT_TRUE(c.purgeDeletedItems(now + std::chrono::seconds(1), true).empty());
  EXPECT_TRUE(c.item(id, true));

  auto released = c.purgeDeletedItems(now + std::chrono::seconds(1), false);
  std::sort(released.begin(), released.end());
  EXPECT_EQ(released, (std::vector<std::string>{sha('c'), sha('d'), sha('e')}));
  EXPECT_FALSE(c.item(id, true));
  EXPECT_TRUE(c.job(job));  // the job list is history
  EXPECT_EQ(c.job(job)->dressedSha256, "");
  // The dressed frame goes; the bare frame is the calibration's, the cutout the other item's.
  EXPECT_EQ(c.dropUnreferencedImages(released), std::vector<std::string>{sha('d')});
  ASSERT_TRUE(c.item(keep));
  EXPECT_EQ(c.item(keep)->images.size(), 2u);
  for (const auto& e : c.outbox(1000))
    EXPECT_NE(e.itemId, id);
  EXPECT_EQ(c.integrityCheck(), "ok");
}

TEST(CatalogStorage, FailedCapturesKeepTheirFramesForTheRetentionOnly) {
  test::TempDir dir;
  Catalog c(dir.path() / "c.sqlite");
  c.addImage(sha('e'), "image/png", 10);
  c.addCalibration(sha('e'), {{"scale", 1}});
  const auto job = c.addJob("dressed", "");
  c.addImage(sha('f'), "image/png", 100);
  c.setJobFrames(job, sha('e'), sha('f'));
  c.failJob(job, "no garment was found on the form");
  const auto now = std::chrono::system_clock::now();
  EXPECT_TRUE(c.forgetFailedJobFrames(now - std::chrono::hours(24 * 14)).empty());
  EXPECT_TRUE(c.dropUnreferencedImages().empty());
  const auto released = c.forgetFailedJobFrames(now + std::chrono::seconds(1));
  EXPECT_EQ(released.size(), 2u);
  EXPECT_EQ(c.job(job)->state, "failed");
  EXPECT_EQ(c.job(job)->error, "no garment was found on the form");
  EXPECT_EQ(c.dropUnreferencedImages(released), std::vector<std::string>{sha('f')});
}

TEST(Catalog, SearchFilterAndPaging) {
  test::TempDir dir;
  Catalog c(dir.path() / "c.sqlite");
  c.addImage(sha('e'), "image/png", 10);
  const auto cal = c.addCalibration(sha('e'), {});
  for (int i = 0; i < 12; ++i) {
    NewItem n = sampleItem(c.addJob("dressed", ""), cal);
    n.sku = "SKU-" + std::to_string(i);
    n.type = i % 3 == 0 ? "skirt" : "dress";
    n.title = i == 7 ? "Linen Summer skirt" : "item";
    if (i == 4)
      n.attributes["color"] = "Navy/White";
    c.addItem(n);
  }
  ItemQuery q;
  q.limit = 5;
  auto [page, total] = c.items(q);
  EXPECT_EQ(total, 12);
  ASSERT_EQ(page.size(), 5u);
  EXPECT_GT(page[0].id, page[1].id);  // newest first
  q.offset = 10;
  EXPECT_EQ(c.items(q).first.size(), 2u);
  ItemQuery t;
  t.type = "skirt";
  EXPECT_EQ(c.items(t).second, 4);
  ItemQuery s;
  s.search = "summer";  // case-insensitive
  auto found = c.items(s);
  ASSERT_EQ(found.second, 1);
  EXPECT_EQ(found.first[0].sku, "SKU-7");
  // Untitled pieces are found by what the station saw: their type and colour.
  ItemQuery byType;
  byType.search = "SKIRT";
  EXPECT_EQ(c.items(byType).second, 5);  // four skirts and the dress titled "... skirt"
  ItemQuery byColour;
  byColour.search = "navy";
  found = c.items(byColour);
  ASSERT_EQ(found.second, 1);
  EXPECT_EQ(found.first[0].sku, "SKU-4");
  ItemQuery inj;
  inj.search = "' OR 1=1 --";  // bound, never concatenated
  EXPECT_EQ(c.items(inj).second, 0);
}

TEST(Catalog, RunningJobsFailAtOpenQueuedOnesWaitOrExpire) {
  test::TempDir dir;
  Catalog c(dir.path() / "c.sqlite");
  const auto a = c.addJob("dressed", "SKU-1");
  const auto b = c.addJob("empty", "");
  c.updateJob(b, "running", "capturing", 0.1);
  const auto done = c.addJob("empty", "");
  c.finishJob(done, std::nullopt, std::nullopt);
  c.addJob("rerun", "", 42);
  const auto ids = c.failInterruptedJobs("interrupted");
  ASSERT_EQ(ids, std::vector<std::int64_t>{b});
  EXPECT_EQ(c.job(b)->state, "failed");
  EXPECT_NE(c.job(b)->error.find("capturing"), std::string::npos);
  EXPECT_EQ(c.job(done)->state, "done");
  // Queued jobs are kept for the station to resume, oldest first, with what they need.
  auto queued = c.queuedJobs();
  ASSERT_EQ(queued.size(), 2u);
  EXPECT_EQ(queued[0].id, a);
  EXPECT_EQ(queued[0].sku, "SKU-1");
  EXPECT_EQ(queued[1].itemId, 42);
  EXPECT_TRUE(c.expireQueuedJobs(std::chrono::hours(1), "expired").empty());
  std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_EQ(c.expireQueuedJobs(std::chrono::seconds(0), "expired").size(), 2u);
  EXPECT_EQ(c.job(a)->state, "failed");
  EXPECT_EQ(c.job(a)->error, "expired");
  EXPECT_TRUE(c.queuedJobs().empty());
}

TEST(Catalog, MigratesVersion1Fixture) {
  test::TempDir dir;
  const auto file = dir.path() / "old.sqlite";
  {
    std::ifstream in(std::string(GARMCAP_TEST_DATA_DIR) + "/daemon/catalog_v1.sql");
    ASSERT_TRUE(in) << "fixture missing";
    std::stringstream sql;
    sql << in.rdbuf();
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(file.c_str(), &db), SQLITE_OK);
    char* err = nullptr;
    ASSERT_EQ(sqlite3_exec(db, sql.str().c_str(), nullptr, nullptr, &err), SQLITE_OK)
        << (err ? err : "");
    sqlite3_close(db);
  }
  Catalog c(file);
  EXPECT_EQ(c.schemaVersion(), kCatalogSchemaVersion);  // through 2 and 3
  EXPECT_EQ(c.integrityCheck(), "ok");
  EXPECT_FALSE(c.setting("shop"));  // v3: the settings table, empty
  auto one = c.item(1);
  ASSERT_TRUE(one);
  EXPECT_EQ(one->status, kStatusApproved);  // 'active' in v1
  EXPECT_EQ(one->attributes.at("skirt"), "a_line");
  EXPECT_DOUBLE_EQ(one->measurementsCm.at("hip_circ"), 94.0);
  EXPECT_TRUE(one->warnings.empty());
  EXPECT_EQ(c.item(2)->status, kStatusNeedsReview);  // 'draft' in v1
  EXPECT_EQ(c.job(1)->dressedSha256, "");
  // Reopening an up-to-date file is a no-op.
  Catalog again(file);
  EXPECT_EQ(again.schemaVersion(), kCatalogSchemaVersion);
}

TEST(Catalog, SettingsSurviveReopeningAndReplaceTheirOldValue) {
  test::TempDir dir;
  const auto file = dir.path() / "c.sqlite";
  {
    Catalog c(file);
    EXPECT_FALSE(c.setting("shop"));
    c.setSetting("shop", {{"brand", "Atelier"}});
    c.setSetting("shop", {{"brand", "Atelier Nord"}, {"currency", "SEK"}});
  }
  Catalog c(file);
  const auto shop = c.setting("shop");
  ASSERT_TRUE(shop);
  EXPECT_EQ(shop->at("brand"), "Atelier Nord");
  EXPECT_EQ(shop->at("currency"), "SEK");
  // A value that is not JSON (a hand edit gone wrong) is an error naming the key, not a default.
  ASSERT_EQ(sqlite3_exec(c.handle(), "UPDATE settings SET value = '{oops' WHERE key = 'shop'",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  try {
    c.setting("shop");
    FAIL() << "a broken setting was read";
  } catch (const CatalogError& e) {
    EXPECT_NE(std::string(e.what()).find("'shop'"), std::string::npos) << e.what();
  }
}

TEST(Catalog, RefusesNewerSchemaAndForeignFiles) {
  test::TempDir dir;
  {
    Catalog c(dir.path() / "new.sqlite");
    ASSERT_EQ(sqlite3_exec(c.handle(), "PRAGMA user_version = 99", nullptr, nullptr, nullptr),
              SQLITE_OK);
  }
  try {
    Catalog c(dir.path() / "new.sqlite");
    FAIL() << "opened a newer schema";
  } catch (const CatalogError& e) {
    EXPECT_NE(std::string(e.what()).find("newer"), std::string::npos) << e.what();
  }
  {
    sqlite3* db = nullptr;
    sqlite3_open((dir.path() / "other.sqlite").c_str(), &db);
    sqlite3_exec(db, "CREATE TABLE x(a); PRAGMA application_id = 5", nullptr, nullptr, nullptr);
    sqlite3_close(db);
  }
  EXPECT_THROW(Catalog(dir.path() / "other.sqlite"), CatalogError);
}

TEST(ContentStore, Sha256KnownVectorsAndDurablePut) {
  EXPECT_EQ(sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_TRUE(isSha256Hex(sha256Hex("x")));
  EXPECT_FALSE(isSha256Hex("../etc/passwd"));
  EXPECT_FALSE(isSha256Hex(std::string(64, 'G')));
  test::TempDir dir;
  ContentStore store(dir.path() / "blobs");
  const std::string a = store.put("hello");
  EXPECT_EQ(a, sha256Hex("hello"));
  EXPECT_EQ(store.put("hello"), a);
  EXPECT_EQ(*store.read(a), "hello");
  EXPECT_FALSE(store.read(sha256Hex("nope")));
  EXPECT_FALSE(store.path("../../etc/passwd"));
  const std::string b = store.put("orphan");
  std::ofstream(dir.path() / "blobs" / "tmp" / "half.tmp") << "partial";
  EXPECT_EQ(store.sweepOrphans({a}), 1u);
  EXPECT_TRUE(store.contains(a));
  EXPECT_FALSE(store.contains(b));
  EXPECT_TRUE(std::filesystem::is_empty(dir.path() / "blobs" / "tmp"));
}

}  // namespace
}  // namespace garmcap::daemon
