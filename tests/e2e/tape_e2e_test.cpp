// Issue 15 part 7 on the real daemon over loopback: staff tape three captured garments, the next
// capture's result.json and catalog carry the fitted correction (with the raw reading), items
// filed before are not rewritten, a re-run is corrected, and bad tape requests are refused with
// the field named.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "daemon_harness.h"

namespace {

// What a shell command prints, then "exit <status>".
std::string commandOutput(const std::string& cmd) {
  std::string out;
  if (FILE* p = popen(cmd.c_str(), "r")) {
    char buf[512];
    while (std::fgets(buf, sizeof buf, p))
      out += buf;
    out += "exit " + std::to_string(pclose(p));
  }
  return out;
}

using namespace garmcap::e2e;

TEST(TapeE2E, ThreeTapedGarmentsCorrectTheNextCapture) {
  TempDir dir;
  Daemon d(dir.path(), {}, makeSimulatedRig(dir.path()));
  ASSERT_EQ(d.waitJob(d.post("/api/capture/empty").json()["job"])["state"], "done");
  std::vector<std::int64_t> items;
  std::vector<double> rawHem;
  for (int i = 0; i < 3; ++i) {
    auto job = d.waitJob(d.post("/api/capture").json()["job"]);
    ASSERT_EQ(job["state"], "done") << job.dump();
    items.push_back(job["item_id"]);
    const Json item = d.get("/api/items/" + std::to_string(items.back())).json();
    ASSERT_EQ(item["type"], "skirt") << item.dump();
    ASSERT_TRUE(item["measurements"].contains("hem_circ")) << item.dump();
    rawHem.push_back(item["measurements"]["hem_circ"]);
  }
  // The tape says the hem is 3.5 cm larger than the station read it, every time.
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Json body = {{"item", items[i]}, {"measurements", {{"hem_circ", rawHem[i] + 3.5}}}};
    const auto r = d.post("/api/tape", body.dump());
    ASSERT_EQ(r.status, 200) << r.body;
    EXPECT_EQ(r.json()["tape"].size(), 1u) << r.body;
  }
  const Json list = d.get("/api/tape").json();
  EXPECT_EQ(list["tape"].size(), 3u) << list.dump();
  ASSERT_EQ(list["corrections"].size(), 1u) << list.dump();
  EXPECT_EQ(list["corrections"][0]["kind"], "offset");
  EXPECT_EQ(list["corrections"][0]["n"], 3);
  EXPECT_NEAR(list["corrections"][0]["offset_cm"].get<double>(), 3.5, 1e-3);

  // The next capture is corrected; result.json says so and keeps the raw value.
  auto job = d.waitJob(d.post("/api/capture").json()["job"]);
  ASSERT_EQ(job["state"], "done") << job.dump();
  const std::string next = std::to_string(job["item_id"].get<std::int64_t>());
  const Json result = d.get("/api/items/" + next + "/result.json").json();
  ASSERT_TRUE(result.contains("corrections")) << result.dump();
  const Json& c = result["corrections"]["hem_circ"];
  EXPECT_EQ(c["kind"], "offset");
  EXPECT_EQ(c["n"], 3);
  EXPECT_NEAR(c["offset_cm"].get<double>(), 3.5, 1e-3);
  EXPECT_TRUE(c.contains("residual_cm"));
  const double raw = c["raw_cm"];
  EXPECT_NEAR(raw, rawHem[0], 0.5) << "the same scene reads about the same";
  EXPECT_NEAR(result["measurements"]["hem_circ"].get<double>(), raw + 3.5, 1e-6);
  const Json item = d.get("/api/items/" + next).json();
  EXPECT_NEAR(item["measurements"]["hem_circ"].get<double>(), raw + 3.5, 1e-6);
  EXPECT_FALSE(result["corrections"].contains("waist_circ")) << "nothing taped, nothing changed";
  // The size run is graded from the corrected reading: the item's own row holds it.
  const Json guide = d.get("/api/items/" + next + "/sizeguide.json").json();
  bool sawBase = false;
  for (const auto& row : guide.value("rows", Json::array()))
    if (row.value("size", "") == guide.value("base_size", "") &&
        row["garment"].contains("hem_circ")) {
      sawBase = true;
      EXPECT_NEAR(row["garment"]["hem_circ"].get<double>(), raw + 3.5, 0.051) << guide.dump();
    }
  EXPECT_TRUE(sawBase) << guide.dump();
  // A correction never adds a reading the capture did not make.
  for (const auto& [name, v] : result["measurements"].items())
    EXPECT_TRUE(item["measurements"].contains(name)) << name;

  // Items filed before are not rewritten; a re-run is corrected.
  const std::string first = std::to_string(items[0]);
  EXPECT_DOUBLE_EQ(d.get("/api/items/" + first).json()["measurements"]["hem_circ"].get<double>(),
                   rawHem[0]);
  EXPECT_FALSE(d.get("/api/items/" + first + "/result.json").json().contains("corrections"));
  auto rerun = d.waitJob(d.post("/api/items/" + first + "/rerun").json()["job"]);
  ASSERT_EQ(rerun["state"], "done") << rerun.dump();
  EXPECT_TRUE(d.get("/api/items/" + first + "/result.json").json().contains("corrections"));
  // Taping a corrected item again stores its raw reading, not the corrected one.
  ASSERT_EQ(
      d.post("/api/tape",
             Json{{"item", std::stoll(next)}, {"measurements", {{"hem_circ", raw + 3.5}}}}.dump())
          .status,
      200);
  const auto tape = d.get("/api/tape").json()["tape"];  // a copy: the parsed body is a temporary
  for (const auto& row : tape)
    if (row["item"] == std::stoll(next)) {
      EXPECT_DOUBLE_EQ(row["measured_cm"].get<double>(), raw);
    }

  // Refusals name the field; nothing is stored.
  auto expect400 = [&](const std::string& body, const std::string& needle) {
    const auto r = d.post("/api/tape", body);
    EXPECT_EQ(r.status, 400) << body << " -> " << r.body;
    EXPECT_NE(r.body.find(needle), std::string::npos) << body << " -> " << r.body;
  };
  expect400(R"({"item": 424242, "measurements": {"hem_circ": 90}})", "field 'item'");
  expect400(R"({"item": )" + first + R"(, "measurements": {"bust_circ": 90}})",
            "measurements.bust_circ");
  expect400(R"({"item": )" + first + R"(, "measurements": {"hem_circ": -1}})",
            "measurements.hem_circ");
  expect400(R"({"item": )" + first + R"(, "measurements": {"hem_circ": 1e999}})", "");
  expect400(R"({"item": )" + first + R"(, "measurements": {"hem_circ": 401}})",
            "measurements.hem_circ");
  EXPECT_EQ(d.get("/api/tape").json()["tape"].size(), 4u);
  // Writes take JSON only (the guard), and a delete of an untaped item is a 404.
  EXPECT_EQ(httpCallWith(d.port(), http::verb::post, "/api/tape",
                         {{"Host", "127.0.0.1"}, {"Content-Type", "text/plain"}},
                         R"({"item": 1, "measurements": {"hem_circ": 90}})")
                .status,
            415);
  EXPECT_EQ(httpCall(d.port(), http::verb::delete_, "/api/tape/424242").status, 404);
  const auto del = httpCall(d.port(), http::verb::delete_, "/api/tape/" + first);
  EXPECT_EQ(del.status, 200) << del.body;
  EXPECT_EQ(d.get("/api/tape").json()["tape"].size(), 3u);

  // The command line takes the same body (here the measurements alone, with --item) and lists.
  const auto run = [&](const std::string& args, const std::string& input) {
    return commandOutput("echo '" + input +
                         "' | GARMCAPD_URL=http://127.0.0.1:" + std::to_string(d.port()) + " " +
                         GARMCAP_BIN_DIR + "/garmcapctl tape " + args + " 2>&1");
  };
  const double waist = item["measurements"]["waist_circ"];
  const std::string posted =
      run("--item " + next + " --json -", Json{{"waist_circ", waist + 1}}.dump());
  EXPECT_NE(posted.find("\"waist_circ\""), std::string::npos) << posted;
  EXPECT_NE(posted.find("exit 0"), std::string::npos) << posted;
  const std::string listed = run("--list", "");
  EXPECT_NE(listed.find("hem_circ"), std::string::npos) << listed;
  EXPECT_NE(listed.find("(tape 2 more)"), std::string::npos) << listed;  // waist: 1 of 3
  const std::string bad = run("--item " + next + " --json -", R"({"waist_circ": 0})");
  EXPECT_NE(bad.find("HTTP 400"), std::string::npos) << bad;
  EXPECT_EQ(d.terminate(), 0);

  // garmcap tape on the stopped station's catalog: the same checks and table.
  const auto offline = [&](const std::string& args, const std::string& input) {
    return commandOutput("echo '" + input + "' | " + GARMCAP_BIN_DIR + "/garmcap tape --data " +
                         dir.path().string() + " " + args + " 2>&1");
  };
  const std::string table = offline("--list", "");
  EXPECT_NE(table.find("offset"), std::string::npos) << table;
  EXPECT_NE(table.find("4 taped measurement(s)"), std::string::npos) << table;
  const std::string refused = offline("--item " + first + " --json -", R"({"hem_circ": 1000})");
  EXPECT_NE(refused.find("measurements.hem_circ"), std::string::npos) << refused;
  EXPECT_EQ(refused.find("exit 0"), std::string::npos) << refused;
  const std::string stored =
      offline("--item " + first + " --json -", Json{{"hem_circ", rawHem[0] + 3.5}}.dump());
  EXPECT_NE(stored.find("exit 0"), std::string::npos) << stored;
  EXPECT_NE(offline("--list", "").find("5 taped measurement(s)"), std::string::npos);
}

}  // namespace
