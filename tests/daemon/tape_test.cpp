// The tape measure's storage (catalog schema 4) and its request checks (daemon/tape.h), on a
// temporary catalog: upgrade from a schema-3 file, rows kept with the raw reading, every refusal
// naming its field, and the correction table fitted from what is stored.
#include "garmcap/daemon/tape.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include "garmcap/daemon/catalog.h"
#include "garmcap/daemon/http_router.h"
#include "test_util.h"

namespace garmcap::daemon {
namespace {

std::int64_t addSkirt(Catalog& c, double hem, bool corrected = false) {
  NewItem n;
  n.type = "skirt";
  n.measurementsCm = {{"hem_circ", hem + (corrected ? 4 : 0)}, {"waist_circ", 70}};
  n.result = {{"type", "skirt"}, {"measurements", n.measurementsCm}};
  if (corrected)
    n.result["corrections"] = {{"hem_circ", {{"kind", "offset"}, {"raw_cm", hem}}}};
  return c.addItem(n);
}

std::string refusal(Catalog& c, const nlohmann::json& body) {
  try {
    const TapeRequest r = parseTapeRequest(body);
    c.setTape(r.itemId, tapeEntriesFor(c, r));
  } catch (const BadRequest& e) {
    return e.what();
  }
  return "";
}

TEST(Tape, MigratesASchema3CatalogAndKeepsItsItems) {
  test::TempDir dir;
  const auto file = dir.path() / "v3.sqlite";
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(file.c_str(), &db), SQLITE_OK);
    const std::string sql = catalogSchemaSql(3) +
                            "PRAGMA application_id = " + std::to_string(kCatalogApplicationId) +
                            "; PRAGMA user_version = 3;"
                            "INSERT INTO items(id, type, created_at, updated_at) VALUES "
                            "(1, 'skirt', 't', 't');";
    char* err = nullptr;
    ASSERT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &err), SQLITE_OK) << err;
    sqlite3_close(db);
  }
  Catalog c(file);
  EXPECT_EQ(c.schemaVersion(), kCatalogSchemaVersion);  // 3 to 4 and on
  EXPECT_EQ(c.integrityCheck(), "ok");
  EXPECT_TRUE(c.tapes().empty());
  ASSERT_TRUE(c.item(1));
  c.setTape(1, {{1, "hem_circ", "skirt", 104, 100, ""}});
  EXPECT_EQ(c.tapes().size(), 1u);
}

TEST(Tape, StoresTheRawReadingBesideTheTapeAndFitsFromIt) {
  test::TempDir dir;
  Catalog c(dir.path() / "c.sqlite");
  std::vector<std::int64_t> ids;
  for (int i = 0; i < 3; ++i) {
    // The third item was itself corrected (+4): its raw reading, 102, is what is stored.
    ids.push_back(addSkirt(c, 100.0 + i, i == 2));
    c.setTape(ids.back(),
              tapeEntriesFor(c, parseTapeRequest({{"item", ids.back()},
                                                  {"measurements", {{"hem_circ", 105.0 + i}}}})));
  }
  const auto rows = c.tapes();
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_DOUBLE_EQ(rows[2].measuredCm, 102);
  EXPECT_EQ(rows[2].type, "skirt");
  const auto table = tapeCorrections(c);
  ASSERT_EQ(table.corrections.size(), 1u);
  EXPECT_NEAR(table.corrections.at({"skirt", "hem_circ"}).offsetCm, 5, 1e-12);
  // Taping again replaces the row; a deleted item's rows are not fitted on.
  c.setTape(ids[0], {{ids[0], "hem_circ", "skirt", 200, 100, ""}});
  EXPECT_EQ(c.tapes(ids[0]).size(), 1u);
  EXPECT_DOUBLE_EQ(c.tapes(ids[0])[0].tapeCm, 200);
  ASSERT_TRUE(c.deleteItem(ids[0]));
  EXPECT_EQ(c.tapes().size(), 2u);
  EXPECT_TRUE(tapeCorrections(c).corrections.empty());
  EXPECT_EQ(c.deleteTape(ids[1]), 1);
  EXPECT_EQ(c.deleteTape(ids[1]), 0);
}

TEST(Tape, RefusalsNameTheField) {
  test::TempDir dir;
  Catalog c(dir.path() / "c.sqlite");
  const auto id = addSkirt(c, 100);
  const auto m = [&](nlohmann::json ms) {
    return nlohmann::json{{"item", id}, {"measurements", ms}};
  };
  EXPECT_NE(refusal(c, {{"item", 999}, {"measurements", {{"hem_circ", 100}}}}).find("field 'item'"),
            std::string::npos);
  EXPECT_NE(refusal(c, {{"item", "1"}, {"measurements", {{"hem_circ", 100}}}}).find("field 'item'"),
            std::string::npos);
  EXPECT_NE(refusal(c, {{"item", id}}).find("field 'measurements'"), std::string::npos);
  EXPECT_NE(refusal(c, m({{"bust_circ", 90}})).find("measurements.bust_circ"),
            std::string::npos);  // a skirt has no bust
  EXPECT_NE(refusal(c, m({{"skirt_length", 60}})).find("not measured"),
            std::string::npos);  // the capture did not read it
  EXPECT_NE(refusal(c, m({{"hem_circ", 0}})).find("measurements.hem_circ"), std::string::npos);
  EXPECT_NE(refusal(c, m({{"hem_circ", -3}})).find("measurements.hem_circ"), std::string::npos);
  EXPECT_NE(refusal(c, m({{"hem_circ", 400.5}})).find("measurements.hem_circ"), std::string::npos);
  EXPECT_NE(refusal(c, m({{"hem_circ", "100"}})).find("measurements.hem_circ"), std::string::npos);
  EXPECT_NE(refusal(c, m({{"Hem", 100}})).find("not a measurement name"), std::string::npos);
  EXPECT_NE(refusal(c, {{"item", id}, {"measurements", {{"hem_circ", 100}}}, {"x", 1}})
                .find("unknown field 'x'"),
            std::string::npos);
  nlohmann::json many = nlohmann::json::object();
  for (int i = 0; i < 40; ++i)
    many["m" + std::to_string(i)] = 1;
  EXPECT_NE(refusal(c, m(many)).find("at most 32"), std::string::npos);
  EXPECT_TRUE(c.tapes().empty()) << "a refused request stores nothing";
  EXPECT_EQ(refusal(c, m({{"hem_circ", 400}})), "");
}

}  // namespace
}  // namespace garmcap::daemon
