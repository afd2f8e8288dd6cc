// The outbox of changes for the hub: one row per item change, in the change's own transaction.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include "garmcap/daemon/catalog.h"
#include "test_util.h"

namespace garmcap::daemon {
namespace {

NewItem item(const std::string& sku) {
  NewItem n;
  n.sku = sku;
  n.title = "Skirt " + sku;
  n.type = "skirt";
  n.measurementsCm = {{"waist_circ", 70.0}};
  n.images = {{"dressed", std::string(64, 'a'), "image/png", 10}};
  n.needsReview = true;
  return n;
}

std::vector<std::pair<std::string, std::int64_t>> kinds(Catalog& c) {
  std::vector<std::pair<std::string, std::int64_t>> out;
  for (const auto& e : c.outbox(1000))
    out.emplace_back(e.kind, e.itemId);
  return out;
}

void sql(Catalog& c, const char* text) {
  char* err = nullptr;
  ASSERT_EQ(sqlite3_exec(c.handle(), text, nullptr, nullptr, &err), SQLITE_OK) << err;
}

TEST(CatalogOutbox, EveryItemChangeQueuesOneRowInOrder) {
  test::TempDir dir;
  Catalog c(dir.path() / "c.sqlite");
  EXPECT_EQ(c.outboxSize(), 0);
  const auto a = c.addItem(item("A"));
  const auto b = c.addItem(item("B"));
  ItemPatch p;
  p.title = "renamed";
  ASSERT_TRUE(c.patchItem(a, p));
  ASSERT_TRUE(c.deleteItem(b));
  ASSERT_TRUE(c.restoreItem(b));
  c.replaceItemResults(a, item("A"));
  using V = std::vector<std::pair<std::string, std::int64_t>>;
  EXPECT_EQ(kinds(c), (V{{kOutboxUpsert, a},
                         {kOutboxUpsert, b},
                         {kOutboxUpsert, a},
                         {kOutboxDelete, b},
                         {kOutboxUpsert, b},
                         {kOutboxUpsert, a}}));
  // Sequence ids only grow.
  const auto rows = c.outbox(1000);
  for (std::size_t i = 1; i < rows.size(); ++i)
    EXPECT_LT(rows[i - 1].seq, rows[i].seq);
  // Changes that change nothing queue nothing.
  EXPECT_FALSE(c.patchItem(999, p));
  ASSERT_TRUE(c.deleteItem(a));
  EXPECT_FALSE(c.deleteItem(a));
  EXPECT_FALSE(c.restoreItem(b));  // b is live
  EXPECT_EQ(c.outboxSize(), 7);
}

TEST(CatalogOutbox, TheRowCommitsOrRollsBackWithTheChange) {
  test::TempDir dir;
  Catalog c(dir.path() / "c.sqlite");
  const auto a = c.addItem(item("A"));
  // An outbox insert that fails must take the item change with it (one transaction).
  sql(c, "CREATE TRIGGER no_outbox BEFORE INSERT ON outbox BEGIN SELECT RAISE(ABORT, 'full'); END");
  EXPECT_THROW(c.addItem(item("B")), CatalogError);
  ItemPatch p;
  p.title = "lost";
  EXPECT_THROW(c.patchItem(a, p), CatalogError);
  EXPECT_THROW(c.deleteItem(a), CatalogError);
  ItemQuery all;
  EXPECT_EQ(c.items(all).second, 1);
  EXPECT_EQ(c.item(a)->title, "Skirt A");
  EXPECT_EQ(c.outboxSize(), 1);
  // And an item change that fails leaves no outbox row behind.
  sql(c, "DROP TRIGGER no_outbox");
  NewItem bad = item("C");
  bad.calibrationId = 4242;  // no such calibration: the foreign key refuses the insert
  EXPECT_THROW(c.addItem(bad), CatalogError);
  EXPECT_EQ(c.outboxSize(), 1);
}

TEST(CatalogOutbox, HubEditsAreAppliedWithoutQueueing) {
  test::TempDir dir;
  Catalog c(dir.path() / "c.sqlite");
  const auto a = c.addItem(item("A"));
  ASSERT_TRUE(c.removeOutbox(c.outbox().front().seq));
  EXPECT_FALSE(c.removeOutbox(12345));
  HubEdit e;
  e.title = "From the hub";
  e.priceCents = std::optional<std::int64_t>(4900);
  e.status = std::string(kStatusApproved);
  ASSERT_TRUE(c.applyHubEdit(a, e));
  const auto it = c.item(a);
  EXPECT_EQ(it->title, "From the hub");
  EXPECT_EQ(it->priceCents, 4900);
  EXPECT_EQ(it->status, kStatusApproved);
  EXPECT_EQ(c.outboxSize(), 0);
  HubEdit bad;
  bad.status = "sold";
  EXPECT_THROW(c.applyHubEdit(a, bad), CatalogError);
  EXPECT_FALSE(c.applyHubEdit(777, e));
}

TEST(CatalogOutbox, OutboxSurvivesReopenAndStateIsKept) {
  test::TempDir dir;
  std::int64_t a = 0;
  {
    Catalog c(dir.path() / "c.sqlite");
    a = c.addItem(item("A"));
    c.setHubState("changes_cursor", "17");
  }
  Catalog c(dir.path() / "c.sqlite");
  ASSERT_EQ(c.outbox().size(), 1u);
  EXPECT_EQ(c.outbox().front().itemId, a);
  EXPECT_EQ(c.hubState("changes_cursor"), "17");
  EXPECT_EQ(c.hubState("nothing"), std::nullopt);
  // A removed newest row's sequence id is not handed out again.
  const auto seq = c.outbox().front().seq;
  ASSERT_TRUE(c.removeOutbox(seq));
  c.addItem(item("B"));
  EXPECT_GT(c.outbox().front().seq, seq);
}

TEST(CatalogOutbox, MigrationFromVersion2QueuesTheLiveItemsOnce) {
  test::TempDir dir;
  const auto file = dir.path() / "v2.sqlite";
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(file.c_str(), &db), SQLITE_OK);
    const std::string schema = catalogSchemaSql(2) +
                               "PRAGMA application_id = " + std::to_string(kCatalogApplicationId) +
                               "; PRAGMA user_version = 2;"
                               "INSERT INTO items(id, created_at, updated_at) VALUES "
                               "(1, 't', 't'), (2, 't', 't');"
                               "INSERT INTO items(id, created_at, updated_at, deleted_at) VALUES "
                               "(3, 't', 't', 't');";
    char* err = nullptr;
    ASSERT_EQ(sqlite3_exec(db, schema.c_str(), nullptr, nullptr, &err), SQLITE_OK) << err;
    sqlite3_close(db);
  }
  {
    Catalog c(file);
    EXPECT_EQ(c.schemaVersion(), kCatalogSchemaVersion);
    using V = std::vector<std::pair<std::string, std::int64_t>>;
    EXPECT_EQ(kinds(c), (V{{kOutboxUpsert, 1}, {kOutboxUpsert, 2}}));
  }
  Catalog again(file);
  EXPECT_EQ(again.outboxSize(), 2);
}

}  // namespace
}  // namespace garmcap::daemon
