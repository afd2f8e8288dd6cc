// The back shot (issue 17) on the real garmcapd over loopback, from a replay rig rendered here by
// the scene simulator: a top's front (a 10 cm deep round neckline, red) and, as if turned back to
// front, its back (a 2 cm neckline, blue), as tests/pipeline/ghost_mannequin_rig_test.cpp renders
// them. The rig's cases in the order the station takes them: c1 the bare form and the front; c2
// the bare form alone (the first back shot shows no garment and is refused); c3 the back. Label
// e2e.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "common/bundled_form.h"
#include "daemon_harness.h"
#include "garmcap/sim/scene.h"
#include "garmcap/sim/sim.h"

using namespace garmcap::e2e;
using namespace garmcap;

namespace {

sim::Scene frontScene() {
  sim::RandomSceneOptions o;
  o.size = {864, 1152};
  o.hardFraction = 0;
  o.type = "top";
  sim::Scene s =
      sim::randomScene(garmcap::testing::bundledForm(), garmcap::testing::bundledFormPath(), 3, o);
  s.shake = {};
  s.garment.neckline = "round";
  s.garment.neckDepthCm = 10;
  s.fabric.kind = sim::FabricKind::kSolid;
  s.fabric.base = {0.15f, 0.15f, 0.65f};  // red (BGR)
  return s;
}

// The same garment turned back to front: the back's neckline, the back's colour.
sim::Scene backScene(sim::Scene s) {
  s.garment.neckDepthCm = 2;
  s.fabric.base = {0.65f, 0.35f, 0.1f};  // blue
  s.seed += 1000;                        // its own sensor noise
  return s;
}

std::filesystem::path makeBackRig(const std::filesystem::path& root) {
  const auto& form = garmcap::testing::bundledForm();
  const sim::SceneRenderer front(form, frontScene());
  const sim::SceneRenderer back(form, backScene(front.scene()));
  const cv::Mat empty = front.renderEmpty();
  const auto rig = root / "backrig";
  const std::pair<const char*, cv::Mat> dressed[] = {
      {"c1", front.renderDressed()}, {"c2", empty}, {"c3", back.renderDressed()}};
  std::string cases;
  for (const auto& [id, frame] : dressed) {
    std::filesystem::create_directories(rig / id);
    cv::imwrite((rig / id / "empty.png").string(), empty);
    cv::imwrite((rig / id / "dressed.png").string(), frame);
    std::ofstream(rig / id / "truth.json") << R"({"type": "top", "measurements": {}})";
    cases += std::string(cases.empty() ? "" : ", ") + R"({"id": ")" + id + R"(", "dir": ")" + id +
             R"(", "type": "top", "attributes": {}, "hard": false})";
  }
  std::ofstream(rig / "rig.json") << R"({"format": "garmcap-rig", "version": 1, "cases": [)"
                                  << cases << "]}";
  return rig;
}

cv::Mat decoded(const Daemon& d, const Json& item, const std::string& kind,
                const std::string& mediaType) {
  if (!item["images"].contains(kind)) {
    ADD_FAILURE() << "no image " << kind << " in " << item["images"].dump();
    return {};
  }
  const Reply r = d.get(item["images"][kind]["url"].get<std::string>());
  EXPECT_EQ(r.status, 200) << kind;
  EXPECT_EQ(r.contentType, mediaType) << kind;
  const std::vector<unsigned char> bytes(r.body.begin(), r.body.end());
  cv::Mat m = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  EXPECT_FALSE(m.empty()) << kind << " does not decode";
  return m;
}

}  // namespace

TEST(BackShotE2E, BareFormRefusedThenTheBackAndGhostPhotosAdded) {
  TempDir dir;
  const auto data = dir.path() / "data";
  const auto db = data / "catalog.sqlite";
  Daemon d(data, {}, makeBackRig(dir.path()));
  ASSERT_EQ(d.waitJob(d.post("/api/capture/empty").json()["job"])["state"], "done");
  const Json captured = d.waitJob(d.post("/api/capture", R"({"sku": "TOP-1"})").json()["job"]);
  ASSERT_EQ(captured["state"], "done") << captured.dump();
  const std::string itemUrl = "/api/items/" + captured["item_id"].dump();
  const Json before = d.get(itemUrl).json();
  const Reply patternBefore = d.get(itemUrl + "/pattern.json");
  ASSERT_FALSE(before["measurements"].empty()) << before.dump();
  EXPECT_FALSE(before["images"].contains("product_back"));

  // Unknown item: 404 before any still is taken.
  EXPECT_EQ(d.post("/api/items/424242/back").status, 404);

  // The bare form as the back shot: refused with the library's sentence, the item as it was.
  const Reply refusedReply = d.post(itemUrl + "/back");
  ASSERT_EQ(refusedReply.status, 202) << refusedReply.body;
  const Json refused = d.waitJob(refusedReply.json()["job"]);
  EXPECT_EQ(refused["kind"], "back");
  EXPECT_EQ(refused["state"], "failed") << refused.dump();
  EXPECT_EQ(refused["error"].get<std::string>().rfind("the back shot: ", 0), 0u) << refused.dump();
  const Json unchanged = d.get(itemUrl).json();
  EXPECT_EQ(unchanged["images"], before["images"]);
  EXPECT_EQ(unchanged["measurements"], before["measurements"]);
  EXPECT_EQ(unchanged["updated_at"], before["updated_at"]);
  EXPECT_NE(d.get("/api/status").json()["state"], "error");

  // The garment turned back to front: the back still, the back photos and the ghost-mannequin
  // front are added; the measurements and pattern stay.
  const Json taken = d.waitJob(d.post(itemUrl + "/back").json()["job"]);
  ASSERT_EQ(taken["state"], "done") << taken.dump();
  EXPECT_EQ(taken["item_id"], captured["item_id"]);
  const Json after = d.get(itemUrl).json();
  EXPECT_EQ(after["measurements"], before["measurements"]);
  EXPECT_EQ(after["sizes"], before["sizes"]);
  EXPECT_EQ(after["type"], before["type"]);
  EXPECT_EQ(after["status"], before["status"]);
  for (const auto& [kind, im] : before["images"].items())
    EXPECT_EQ(after["images"][kind], im) << kind << ": a front image changed";
  const Reply patternAfter = d.get(itemUrl + "/pattern.json");
  EXPECT_EQ(patternAfter.status, patternBefore.status);
  EXPECT_EQ(patternAfter.body, patternBefore.body);

  const cv::Mat front = decoded(d, after, "product", "image/jpeg");
  const cv::Mat front45 = decoded(d, after, "product_4x5", "image/jpeg");
  const cv::Mat backStill = decoded(d, after, "back", "image/png");
  const cv::Mat dressed = decoded(d, after, "dressed", "image/png");
  const cv::Mat back = decoded(d, after, "product_back", "image/jpeg");
  const cv::Mat back45 = decoded(d, after, "product_back_4x5", "image/jpeg");
  const cv::Mat ghost = decoded(d, after, "product_ghost", "image/jpeg");
  const cv::Mat ghost45 = decoded(d, after, "product_ghost_4x5", "image/jpeg");
  const cv::Mat cutout = decoded(d, after, "cutout_back", "image/png");
  ASSERT_FALSE(front.empty() || back.empty() || ghost.empty() || backStill.empty());
  // The still is the camera's frame, as the dressed one is; the ghost is the front's photo with
  // its neck opening filled (same canvas); the back photos are square and 4:5 like the front's.
  EXPECT_EQ(backStill.size(), dressed.size());
  EXPECT_EQ(ghost.size(), front.size());
  EXPECT_EQ(ghost45.size(), front45.size());
  EXPECT_EQ(back.cols, back.rows);
  EXPECT_NEAR(back45.cols, 0.8 * back45.rows, 1.0);  // 4:5 to the pixel
  EXPECT_EQ(cutout.channels(), 4);
  cv::Mat differs;
  cv::compare(ghost, front, differs, cv::CMP_NE);
  const int changedPx = cv::countNonZero(differs.reshape(1));
  EXPECT_GT(changedPx, 0) << "the ghost photo is the plain front";
  // Only the neck opening changed: the top's neck is in the upper half of its photo (JPEG blocks
  // are coded apart, so pixels of unchanged 16 px blocks decode the same in both photos).
  cv::Mat anyChannel;
  cv::reduce(differs.reshape(1, differs.rows * differs.cols), anyChannel, 1, cv::REDUCE_MAX);
  const cv::Rect changedBox = cv::boundingRect(anyChannel.reshape(1, differs.rows));
  EXPECT_LT(changedBox.br().y, ghost.rows / 2) << changedBox;
  std::printf(
      "[back] refused: %s\n[back] photos: back %dx%d, back 4:5 %dx%d, ghost %dx%d (front "
      "%dx%d), %d ghost channel values differ from the front, in rows %d-%d\n",
      refused["error"].get<std::string>().c_str(), back.cols, back.rows, back45.cols, back45.rows,
      ghost.cols, ghost.rows, front.cols, front.rows, changedPx, changedBox.y, changedBox.br().y);

  // The shop gets the ghost-mannequin front first and the back second, and catalog.zip holds
  // the photos the CSV links.
  ASSERT_EQ(httpCall(d.port(), http::verb::patch, itemUrl,
                     R"({"status": "approved", "price_cents": 3990})")
                .status,
            200);
  const std::string query = "?base_url=https://shop.example/files&store_url=https://shop.example";
  const Reply shopify = d.get("/api/export/shopify.csv" + query);
  ASSERT_EQ(shopify.status, 200) << shopify.body;
  const std::string id = std::to_string(captured["item_id"].get<std::int64_t>());
  const auto ghostAt = shopify.body.find("/images/" + id + "-product_ghost.jpg");
  const auto backAt = shopify.body.find("/images/" + id + "-product_back.jpg");
  ASSERT_NE(ghostAt, std::string::npos) << shopify.body;
  ASSERT_NE(backAt, std::string::npos) << shopify.body;
  EXPECT_LT(ghostAt, backAt) << "the front goes first";
  EXPECT_EQ(shopify.body.find("/images/" + id + "-product.jpg"), std::string::npos)
      << "the plain front is sent beside its ghost";
  const Reply zip = d.get("/api/export/catalog.zip" + query);
  ASSERT_EQ(zip.status, 200) << zip.body;
  for (const std::string kind : {"product_ghost.jpg", "product_back.jpg"})
    EXPECT_NE(zip.body.find("images/" + id + "-" + kind), std::string::npos) << kind;

  // A re-run of the front keeps the back shot's images.
  const Json rerun = d.waitJob(d.post(itemUrl + "/rerun").json()["job"]);
  ASSERT_EQ(rerun["state"], "done") << rerun.dump();
  const Json rerunItem = d.get(itemUrl).json();
  for (const char* kind : {"back", "product_back", "product_ghost", "cutout_back"})
    EXPECT_EQ(rerunItem["images"][kind], after["images"][kind]) << kind;

  EXPECT_EQ(d.terminate(), 0);
  EXPECT_EQ(integrity(db), "ok");
}

// A back shot queued when garmcapd stops is kept (job kind "back" with its item) and runs at the
// next start.
TEST(BackShotE2E, QueuedBackShotRunsAfterARestart) {
  TempDir dir;
  const auto data = dir.path() / "data";
  const auto rig = makeBackRig(dir.path());
  std::int64_t itemId = 0, queued = 0;
  {
    Daemon d(data, {}, rig);
    ASSERT_EQ(d.waitJob(d.post("/api/capture/empty").json()["job"])["state"], "done");
    const Json captured = d.waitJob(d.post("/api/capture").json()["job"]);
    ASSERT_EQ(captured["state"], "done") << captured.dump();
    itemId = captured["item_id"].get<std::int64_t>();
    // The first back shot holds the camera for 2 s; the second waits in the queue.
    ASSERT_EQ(d.post("/api/sim/camera", R"({"still_delay_ms": 2000})").status, 200);
    const std::string backUrl = "/api/items/" + std::to_string(itemId) + "/back";
    ASSERT_EQ(d.post(backUrl).status, 202);
    queued = d.post(backUrl).json()["job"].get<std::int64_t>();
    EXPECT_EQ(d.get("/api/jobs/" + std::to_string(queued)).json()["state"], "queued");
    EXPECT_EQ(d.terminate(), 0);
  }
  // Stopped with the job still queued in the catalog (not run on the way out, not dropped).
  EXPECT_EQ(column(data / "catalog.sqlite",
                   ("SELECT kind || ' ' || state || ' ' || item_id FROM jobs WHERE id = " +
                    std::to_string(queued))
                       .c_str()),
            std::vector<std::string>{"back queued " + std::to_string(itemId)});
  Daemon d(data, {}, rig);  // a new camera: the rig starts again at the front (same garment)
  const Json resumed = d.waitJob(queued);
  EXPECT_EQ(resumed["kind"], "back");
  EXPECT_EQ(resumed["item_id"], itemId);
  ASSERT_EQ(resumed["state"], "done") << resumed.dump();
  const Json item = d.get("/api/items/" + std::to_string(itemId)).json();
  EXPECT_TRUE(item["images"].contains("back")) << item["images"].dump();
  EXPECT_TRUE(item["images"].contains("product_back")) << item["images"].dump();
  EXPECT_EQ(d.terminate(), 0);
}
