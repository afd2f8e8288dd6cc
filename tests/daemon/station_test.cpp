// The station state machine and the API handlers, with a fake camera and a fake processor, no
// sockets: requests go through Router::dispatch, the event loop is run in bounded slices.
#include "garmcap/daemon/station.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <opencv2/imgproc.hpp>
#include <opencv2/objdetect.hpp>
#include <optional>
#include <set>
#include <vector>

#include "garmcap/daemon/api_routes.h"
#include "garmcap/daemon/capture_processor.h"
#include "garmcap/daemon/station_routes.h"
#include "station_rig.h"

namespace garmcap::daemon {
namespace {

using namespace std::chrono_literals;
using test::Rig;

// The button's path: no SKU typed, so the hang tag is read from the still, beside the pipeline,
// with the calibration's bare frame handed to the scan once it is decoded.
TEST(Station, CaptureWithoutSkuReadsTheHangTag) {
  if (hangTagDecoder() != "zbar")
    GTEST_SKIP() << "built without zbar: no QR code is read";
  Rig rig;
  cv::Mat bare(300, 400, CV_8UC3, cv::Scalar(40, 180, 40));
  cv::rectangle(bare, cv::Rect(120, 40, 160, 260), cv::Scalar(200, 208, 215), cv::FILLED);
  cv::Mat code;
  cv::QRCodeEncoder::create()->encode("TAG-QR-7", code);
  cv::Mat big, tag(0, 0, CV_8UC3);
  cv::resize(code, big, {}, 4, 4, cv::INTER_NEAREST);
  cv::copyMakeBorder(big, big, 16, 16, 16, 16, cv::BORDER_CONSTANT, cv::Scalar(255));
  cv::cvtColor(big, tag, cv::COLOR_GRAY2BGR);
  cv::Mat dressed = bare.clone();
  tag.copyTo(dressed(cv::Rect(150, 120, tag.cols, tag.rows)));
  {
    std::lock_guard lock(rig.camera->deliveredMutex);
    rig.camera->bareStill = bare;
    rig.camera->dressedStill = dressed;
  }
  auto job = rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture/empty"))["job"]);
  ASSERT_EQ(job["state"], "done") << job.dump();
  job = rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture"))["job"]);
  ASSERT_EQ(job["state"], "done") << job.dump();
  const auto item = rig.json(rig.call(
      http::verb::get, "/api/items/" + std::to_string(job["item_id"].get<std::int64_t>())));
  EXPECT_EQ(item["sku"], "TAG-QR-7");
}

TEST(Station, LedPatternsDifferPerState) {
  std::set<int> patterns;
  for (auto s : {StationState::kUncalibrated, StationState::kReady, StationState::kCapturing,
                 StationState::kProcessing, StationState::kError, StationState::kStopping})
    patterns.insert(ledPattern(s));
  EXPECT_EQ(patterns.size(), 6u);
  EXPECT_EQ(ledPattern(StationState::kReady), 0xff);
}

TEST(Station, CalibrateThenCaptureFilesAnItem) {
  Rig rig;
  auto status = rig.json(rig.call(http::verb::get, "/api/status"));
  EXPECT_EQ(status["state"], "uncalibrated");
  // A garment before the bare form is refused with a reason.
  auto refused = rig.call(http::verb::post, "/api/capture");
  EXPECT_EQ(refused.result(), http::status::conflict);
  EXPECT_NE(refused.body().find("bare form"), std::string::npos);

  auto r = rig.call(http::verb::post, "/api/capture/empty");
  ASSERT_EQ(r.result(), http::status::accepted);
  auto job = rig.waitJob(rig.json(r)["job"]);
  EXPECT_EQ(job["state"], "done") << job.dump();
  EXPECT_EQ(rig.json(rig.call(http::verb::get, "/api/status"))["state"], "ready");

  r = rig.call(http::verb::post, "/api/capture", R"({"sku": "TAG-001"})");
  ASSERT_EQ(r.result(), http::status::accepted) << r.body();
  job = rig.waitJob(rig.json(r)["job"]);
  ASSERT_EQ(job["state"], "done") << job.dump();
  const auto itemId = job["item_id"].get<std::int64_t>();
  auto item = rig.json(rig.call(http::verb::get, "/api/items/" + std::to_string(itemId)));
  EXPECT_EQ(item["sku"], "TAG-001");
  EXPECT_EQ(item["type"], "skirt");
  EXPECT_EQ(item["status"], "approved");
  EXPECT_TRUE(item["measurements"].contains("waist_circ"));
  EXPECT_TRUE(item["images"].contains("cutout"));
  EXPECT_TRUE(item["images"].contains("dressed"));
  auto img = rig.call(http::verb::get, "/api/items/" + std::to_string(itemId) + "/images/cutout");
  EXPECT_EQ(img.result(), http::status::ok);
  EXPECT_EQ(img[http::field::content_type], "image/png");
  EXPECT_EQ(img.body().substr(1, 3), "PNG");
  // The shop photo is stored as JPEG (the cut-out keeps its alpha in PNG), and downloads as .jpg.
  img = rig.call(http::verb::get,
                 "/api/items/" + std::to_string(itemId) + "/images/product?download=1");
  EXPECT_EQ(img.result(), http::status::ok);
  EXPECT_EQ(img[http::field::content_type], "image/jpeg");
  EXPECT_EQ(img.body().substr(0, 3), "\xff\xd8\xff");
  EXPECT_NE(std::string(img[http::field::content_disposition]).find(".jpg\""), std::string::npos)
      << img[http::field::content_disposition];
  auto pj = rig.call(http::verb::get, "/api/items/" + std::to_string(itemId) + "/pattern.json");
  EXPECT_EQ(rig.json(pj)["type"], "skirt");
  auto list = rig.json(rig.call(http::verb::get, "/api/items?type=skirt"));
  EXPECT_EQ(list["total"], 1);
}

// Issue 16: a still the camera delivers encoded (a UVC camera's MJPEG still) is stored as it
// came, not PNG-encoded again on the camera thread: the bare form's and the garment's stills are
// served with the camera's own bytes and media type, and a re-run decodes the stored JPEG. A still
// that comes as pixels only stays PNG.
TEST(Station, AStillDeliveredAsJpegIsStoredAsDelivered) {
  Rig rig;
  rig.camera->deliverJpeg = true;
  ASSERT_EQ(rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture/empty"))["job"])["state"],
            "done");
  auto job = rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture"))["job"]);
  ASSERT_EQ(job["state"], "done") << job.dump();
  std::vector<std::string> delivered;
  {
    std::lock_guard lock(rig.camera->deliveredMutex);
    delivered = rig.camera->delivered;
  }
  ASSERT_EQ(delivered.size(), 2u);
  const std::string itemUrl = "/api/items/" + std::to_string(job["item_id"].get<std::int64_t>());
  auto bare = rig.call(http::verb::get, itemUrl + "/images/empty");
  ASSERT_EQ(bare.result(), http::status::ok);
  EXPECT_EQ(bare[http::field::content_type], "image/jpeg");
  EXPECT_TRUE(bare.body() == delivered[0]) << bare.body().size() << " bytes served";
  auto still = rig.call(http::verb::get, itemUrl + "/images/dressed?download=1");
  ASSERT_EQ(still.result(), http::status::ok);
  EXPECT_EQ(still[http::field::content_type], "image/jpeg");
  EXPECT_TRUE(still.body() == delivered[1]) << still.body().size() << " bytes served";
  EXPECT_NE(std::string(still[http::field::content_disposition]).find(".jpg\""), std::string::npos);
  // The processor saw the decoded JPEG: its fake waist is 60 + the first pixel's blue.
  const cv::Mat decoded =
      cv::imdecode(cv::Mat(1, static_cast<int>(delivered[1].size()), CV_8U, delivered[1].data()),
                   cv::IMREAD_COLOR);
  const double waist = 60.0 + decoded.at<cv::Vec3b>(0, 0)[0];
  auto item = rig.json(rig.call(http::verb::get, itemUrl));
  EXPECT_DOUBLE_EQ(item["measurements"]["waist_circ"].get<double>(), waist);
  // A re-run reads the stored JPEG back: the same pixels, the same reading.
  auto rerun = rig.waitJob(rig.json(rig.call(http::verb::post, itemUrl + "/rerun"))["job"]);
  ASSERT_EQ(rerun["state"], "done") << rerun.dump();
  item = rig.json(rig.call(http::verb::get, itemUrl));
  EXPECT_DOUBLE_EQ(item["measurements"]["waist_circ"].get<double>(), waist);
  still = rig.call(http::verb::get, itemUrl + "/images/dressed");
  EXPECT_EQ(still[http::field::content_type], "image/jpeg");

  // Pixels only: PNG, as before.
  rig.camera->deliverJpeg = false;
  job = rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture"))["job"]);
  ASSERT_EQ(job["state"], "done") << job.dump();
  still =
      rig.call(http::verb::get, "/api/items/" + std::to_string(job["item_id"].get<std::int64_t>()) +
                                    "/images/dressed");
  EXPECT_EQ(still[http::field::content_type], "image/png");
  EXPECT_EQ(still.body().substr(1, 3), "PNG");
}

// Issue 16: the pipeline processor encodes the photos beside the colours and the size run; the
// station stores the encodings it is handed instead of encoding the images again.
TEST(Station, PhotosEncodedByTheProcessorAreStoredAsHanded) {
  Rig rig;
  rig.processor->preEncode = true;
  ASSERT_EQ(rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture/empty"))["job"])["state"],
            "done");
  const auto job = rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture"))["job"]);
  ASSERT_EQ(job["state"], "done") << job.dump();
  const std::string itemUrl = "/api/items/" + std::to_string(job["item_id"].get<std::int64_t>());
  const auto cutout = rig.call(http::verb::get, itemUrl + "/images/cutout");
  ASSERT_EQ(cutout.result(), http::status::ok);
  EXPECT_TRUE(cutout.body() == rig.processor->preEncodedCutout)
      << cutout.body().size() << " bytes served";
  const auto product = rig.call(http::verb::get, itemUrl + "/images/product");
  EXPECT_EQ(product[http::field::content_type], "image/jpeg");
}

// Issue 18: nesting a marker keeps a core busy for seconds; 20 marker requests at once must not
// take the station's CPU from captures. One is laid, the others are answered 503 with
// Retry-After straight away, and the slot is free again once the marker is sent.
TEST(Station, MarkersAreLaidOneAtATime) {
  Rig rig;
  addExportRoutes(rig.router, *rig.station);
  rig.processor->draftedPattern = true;
  ASSERT_EQ(rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture/empty"))["job"])["state"],
            "done");
  const auto job = rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture"))["job"]);
  ASSERT_EQ(job["state"], "done") << job.dump();
  const std::string marker =
      "/api/items/" + std::to_string(job["item_id"].get<std::int64_t>()) + "/marker.json";
  std::vector<std::optional<Response>> replies(20);
  for (std::size_t i = 0; i < replies.size(); ++i) {
    Request req{http::verb::get, marker + (i % 2 ? "?width=140" : ""), 11};
    req.prepare_payload();
    rig.router.dispatch(req, [&replies, i](Response r) { replies[i] = std::move(r); });
  }
  ASSERT_TRUE(rig.runUntil(
      [&] {
        return std::all_of(replies.begin(), replies.end(),
                           [](const auto& r) { return r.has_value(); });
      },
      60s));
  int laid = 0, busy = 0;
  for (const auto& r : replies) {
    if (r->result() == http::status::ok) {
      ++laid;
      EXPECT_GT(rig.json(*r)["efficiency"].get<double>(), 0) << r->body();
    } else {
      ASSERT_EQ(r->result(), http::status::service_unavailable) << r->body();
      EXPECT_EQ((*r)[http::field::retry_after], "5");
      EXPECT_NE(rig.json(*r)["error"].get<std::string>().find("one at a time"), std::string::npos);
      ++busy;
    }
  }
  EXPECT_EQ(laid, 1);
  EXPECT_EQ(busy, 19);
  // The slot was given back with the answer: the next request is laid.
  EXPECT_EQ(rig.call(http::verb::get, marker).result(), http::status::ok);
  // And a request refused for its query takes no slot.
  EXPECT_EQ(rig.call(http::verb::get, marker + "?width=20").result(), http::status::bad_request);
  EXPECT_EQ(rig.call(http::verb::get, marker).result(), http::status::ok);
}

// Issue 18: the GarmentCode JSON of every stored size of a graded dress (a graded size was
// refused 422 "seam 'skirt_side' ... does not end on a corner"; the JSON itself is read back
// against the panels in tests/dsw/graded_garmentcode_test.cpp).
TEST(Station, GarmentCodeOfEveryGradedSizeIsServed) {
  Rig rig;
  addExportRoutes(rig.router, *rig.station);
  rig.processor->gradedDress = true;
  ASSERT_EQ(rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture/empty"))["job"])["state"],
            "done");
  const auto job = rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture"))["job"]);
  ASSERT_EQ(job["state"], "done") << job.dump();
  const std::string item = "/api/items/" + std::to_string(job["item_id"].get<std::int64_t>());
  const auto sizes = rig.json(rig.call(http::verb::get, item))["sizes"];
  ASSERT_EQ(sizes.size(), 6u) << sizes.dump();  // base and the chart's five
  for (const auto& size : sizes) {
    const auto r =
        rig.call(http::verb::get, item + "/garmentcode.json?size=" + size.get<std::string>());
    EXPECT_EQ(r.result(), http::status::ok) << size << ": " << r.body().substr(0, 300);
    if (r.result() == http::status::ok) {
      EXPECT_FALSE(rig.json(r)["pattern"]["stitches"].empty()) << size;
    }
  }
}

// Issue 18: the pieces a marker may lay are the station's [marker] max_pieces; a marker over it
// is refused 422 before nesting, naming the count and the limit, and takes no slot for long.
TEST(Station, MarkerPieceLimitIsTheConfigsAndIsNamedWhenExceeded) {
  Rig rig;
  rig.stop();
  rig.config.markerMaxPieces = 1;
  rig.start();
  addExportRoutes(rig.router, *rig.station);
  EXPECT_EQ(rig.station->markerMaxPieces(), 1);
  rig.processor->draftedPattern = true;
  ASSERT_EQ(rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture/empty"))["job"])["state"],
            "done");
  const auto job = rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture"))["job"]);
  ASSERT_EQ(job["state"], "done") << job.dump();
  const std::string marker =
      "/api/items/" + std::to_string(job["item_id"].get<std::int64_t>()) + "/marker.json";
  const auto refused = rig.call(http::verb::get, marker);
  ASSERT_EQ(refused.result(), http::status::unprocessable_entity) << refused.body();
  const std::string error = rig.json(refused)["error"];
  EXPECT_NE(error.find("limit of 1 pieces"), std::string::npos) << error;
  EXPECT_NE(error.find("[marker] max_pieces is 1"), std::string::npos) << error;
  // Raised by a reload, the same marker is laid.
  Config raised = rig.config;
  raised.markerMaxPieces = 60;
  rig.station->reload(raised);
  ASSERT_TRUE(rig.runUntil([&] { return rig.station->markerMaxPieces() == 60; }, 5s));
  const auto laid = rig.call(http::verb::get, marker);
  ASSERT_EQ(laid.result(), http::status::ok) << laid.body();
  EXPECT_LE(rig.json(laid)["piece_count"].get<int>(), 60);
}

TEST(StoreBasePattern, AFailedDraftStoresNoPatternAndSaysWhy) {
  ProcessedCapture out;
  out.warnings = {"no pattern: recipe 'dress': sleeve of 1.1 cm, shorter than 2 cm"};
  storeBasePattern(out, {{"type", "dress"}, {"panels", nlohmann::json::array()}});
  EXPECT_TRUE(out.patterns.empty());
  EXPECT_EQ(out.warnings.size(), 1u) << "the pipeline's own reason is kept, not repeated";
  // No reason given by the pipeline: the warning still says there is no pattern.
  ProcessedCapture silent;
  storeBasePattern(silent, {{"type", "dress"}});
  EXPECT_TRUE(silent.patterns.empty());
  ASSERT_EQ(silent.warnings.size(), 1u);
  EXPECT_EQ(silent.warnings[0].rfind("no pattern: ", 0), 0u) << silent.warnings[0];
  // A drafted pattern is stored as it is.
  ProcessedCapture drafted;
  const nlohmann::json p = {{"type", "skirt"}, {"panels", {{{"name", "skirt_front"}}}}};
  storeBasePattern(drafted, p);
  ASSERT_EQ(drafted.patterns.count("base"), 1u);
  EXPECT_EQ(drafted.patterns["base"], p);
  EXPECT_TRUE(drafted.warnings.empty());
}

TEST(Station, AnItemWithoutADraftedPatternAnswers422NotAnEmptyPattern) {
  // Both a capture since storeBasePattern (no pattern row) and an old catalog's empty row.
  for (const bool legacy : {false, true}) {
    SCOPED_TRACE(legacy ? "empty pattern row (old catalog)" : "no pattern row");
    Rig rig;
    // The pattern file routes too (export_routes.cpp).
    addExportRoutes(rig.router, *rig.station);
    (legacy ? rig.processor->legacyEmptyPattern : rig.processor->undraftable) = true;
    rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture/empty"))["job"]);
    auto job = rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture"))["job"]);
    ASSERT_EQ(job["state"], "done") << job.dump();
    const std::string item = "/api/items/" + job["item_id"].dump();
    const auto stored = rig.json(rig.call(http::verb::get, item));
    if (!legacy) {
      EXPECT_TRUE(stored["sizes"].empty()) << "a failed draft stores no pattern: " << stored.dump();
    }
    EXPECT_NE(stored["warnings"].dump().find(
                  "no pattern: recipe 'dress': sleeve of 1.1 cm, shorter than 2 cm"),
              std::string::npos)
        << stored.dump();
    for (const char* route :
         {"/pattern.json", "/pattern.svg", "/pattern.dxf", "/pattern.pdf", "/garmentcode.json",
          "/pattern.json?size=base", "/pattern.pdf?paper=a0", "/pattern_graded.dxf",
          "/nested_grading.svg", "/marker.json", "/marker.svg?width=140&sizes=base"}) {
      auto r = rig.call(http::verb::get, item + route);
      EXPECT_EQ(r.result(), http::status::unprocessable_entity) << route << ": " << r.body();
      const std::string error = rig.json(r).value("error", "");
      EXPECT_EQ(error.rfind("no pattern: recipe 'dress': sleeve of 1.1 cm, shorter than 2 cm", 0),
                0u)
          << route << ": " << error;
      EXPECT_NE(error.find("could not be drafted"), std::string::npos) << route << ": " << error;
    }
    // A size the item does not have stays a 404 when the item has patterns; here it has none
    // (or only the empty base), so the answer says why instead.
    auto xl = rig.call(http::verb::get, item + "/pattern.json?size=XL");
    EXPECT_EQ(xl.result(), legacy ? http::status::not_found : http::status::unprocessable_entity)
        << xl.body();
  }
}

TEST(Station, LowConfidenceWaitsForReview) {
  Rig rig;
  rig.processor->confidence = 0.3;
  rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture/empty"))["job"]);
  auto job = rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture"))["job"]);
  auto item = rig.json(rig.call(http::verb::get, "/api/items/" + job["item_id"].dump()));
  EXPECT_EQ(item["status"], "needs_review");
  auto ok = rig.call(http::verb::patch, "/api/items/" + job["item_id"].dump(),
                     R"({"status": "approved", "title": "Checked"})");
  EXPECT_EQ(rig.json(ok)["status"], "approved");
}

// Notes on how a reading was made do not hold an item back; a warning that says it may be wrong
// does (daemon/src/review_policy.cpp), and the item lists it under `checks`.
TEST(Station, NotesAloneDoNotHoldAnItemBackButACheckDoes) {
  Rig rig;
  const std::string note =
      "bust_circ: sleeves cover the sides at the bust; read from the sides down to 6 cm lower, "
      "where they show";
  const std::string check =
      "the garment is close to the screen's colour (5 cm2 of it over the form keys as screen); "
      "its outline was found against the bare-form frame, check it";
  rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture/empty"))["job"]);
  rig.processor->warnings = {note};
  auto job = rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture"))["job"]);
  auto item = rig.json(rig.call(http::verb::get, "/api/items/" + job["item_id"].dump()));
  EXPECT_EQ(item["status"], "approved");
  EXPECT_EQ(item["warnings"], nlohmann::json::array({note}));
  EXPECT_EQ(item["checks"], nlohmann::json::array());

  rig.processor->warnings = {note, check};
  job = rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture"))["job"]);
  item = rig.json(rig.call(http::verb::get, "/api/items/" + job["item_id"].dump()));
  EXPECT_EQ(item["status"], "needs_review");
  EXPECT_EQ(item["warnings"], nlohmann::json::array({note, check}));
  EXPECT_EQ(item["checks"], nlohmann::json::array({check}));
}

TEST(Station, PressesDuringAJobAreMergedNotLost) {
  Rig rig;
  rig.camera->delay = 150ms;
  auto first = rig.json(rig.call(http::verb::post, "/api/button"));  // uncalibrated: bare form
  auto second = rig.json(rig.call(http::verb::post, "/api/button"));
  auto third = rig.json(rig.call(http::verb::post, "/api/button"));
  EXPECT_NE(first["job"], second["job"]);
  EXPECT_EQ(second["job"], third["job"]);
  EXPECT_TRUE(third.value("merged", false));
  EXPECT_EQ(rig.waitJob(first["job"])["kind"], "empty");
  auto j2 = rig.waitJob(second["job"]);
  EXPECT_EQ(j2["kind"], "dressed");
  EXPECT_EQ(j2["state"], "done");
  EXPECT_EQ(rig.stills->load(), 2);  // one bare form, one garment: nothing multiplied
}

TEST(Station, FailuresAreJobErrorsAndTheStationRecovers) {
  Rig rig;
  rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture/empty"))["job"]);
  rig.processor->fail = true;
  auto job = rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture"))["job"]);
  EXPECT_EQ(job["state"], "failed");
  EXPECT_EQ(job["error"], "no garment found on the form");
  auto status = rig.json(rig.call(http::verb::get, "/api/status"));
  EXPECT_EQ(status["state"], "ready");
  EXPECT_EQ(status["last_error"], "no garment found on the form");

  rig.processor->fail = false;
  rig.camera->absent = true;
  rig.camera->close();
  job = rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture"))["job"]);
  EXPECT_EQ(job["state"], "failed");
  EXPECT_NE(job["error"].get<std::string>().find("camera"), std::string::npos) << job.dump();
  EXPECT_EQ(rig.json(rig.call(http::verb::get, "/api/status"))["state"], "error");
  rig.camera->absent = false;
  job = rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture"))["job"]);
  EXPECT_EQ(job["state"], "done") << job.dump();
  EXPECT_EQ(rig.json(rig.call(http::verb::get, "/api/status"))["state"], "ready");
}

TEST(Station, StatusShowsTheHubsOutboxAndTheRowsItRefusedForGood) {
  Rig rig;
  EXPECT_FALSE(rig.json(rig.call(http::verb::get, "/api/status")).contains("hub"));
  rig.stop();
  rig.config.hubUrl = "http://127.0.0.1:9";
  rig.config.hubToken = "t";
  rig.start();
  rig.station->setHubStatus([] { return nlohmann::json{{"token_refused", "push: 401 no"}}; });
  bool done = false;
  rig.station->withCatalog(
      [&](Catalog& c) {
        NewItem a;
        a.sku = "A";
        a.type = "skirt";
        NewItem b = a;
        b.sku = "B";
        c.addItem(a);
        c.addItem(b);
        const auto rows = c.outbox(10);
        ASSERT_EQ(rows.size(), 2u);
        ASSERT_TRUE(c.refuseOutbox(rows[0].seq, 422, "push of item 1: 422 bad title"));
        EXPECT_FALSE(c.refuseOutbox(rows[0].seq, 422, "again"));  // gone from the outbox
        done = true;
      },
      [](Response) {});
  ASSERT_TRUE(rig.runUntil([&] { return done; }));
  const auto hub = rig.json(rig.call(http::verb::get, "/api/status"))["hub"];
  EXPECT_EQ(hub["outbox"], 1) << hub.dump();
  EXPECT_EQ(hub["refused_count"], 1);
  ASSERT_EQ(hub["refused"].size(), 1u);
  EXPECT_EQ(hub["refused"][0]["http_status"], 422);
  EXPECT_EQ(hub["refused"][0]["item_id"], 1);
  EXPECT_EQ(hub["refused"][0]["reason"], "push of item 1: 422 bad title");
  EXPECT_EQ(hub["token_refused"], "push: 401 no");
}

TEST(Station, QueueIsBounded) {
  Rig rig;
  rig.camera->delay = 100ms;
  rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture/empty"))["job"]);
  int accepted = 0, refused = 0;
  for (int i = 0; i < 8; ++i) {
    auto r = rig.call(http::verb::post, "/api/capture");
    (r.result() == http::status::accepted ? accepted : refused)++;
  }
  EXPECT_GE(refused, 1);
  EXPECT_LE(accepted, 5);  // queue limit 4 + the running job
}

TEST(Station, QueuedJobsOutliveAStopAndRunAtTheNextStart) {
  Rig rig;
  rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture/empty"))["job"]);
  rig.camera->delay = 200ms;
  auto first = rig.json(rig.call(http::verb::post, "/api/capture", R"({"sku": "A-1"})"))["job"];
  auto queued = rig.json(rig.call(http::verb::post, "/api/capture", R"({"sku": "B-2"})"))["job"];
  rig.stop();  // SIGTERM: the job in hand finishes, the queued one is checkpointed
  {
    Catalog c(rig.dir.path() / "data" / "catalog.sqlite");
    EXPECT_EQ(c.job(first)->state, "done");
    EXPECT_EQ(c.job(queued)->state, "queued");
  }
  rig.start();
  auto j = rig.waitJob(queued);
  ASSERT_EQ(j["state"], "done") << j.dump();
  auto item = rig.json(rig.call(http::verb::get, "/api/items/" + j["item_id"].dump()));
  EXPECT_EQ(item["sku"], "B-2");
}

TEST(Station, StaleQueuedJobsExpireAndResumingCanBeTurnedOff) {
  Rig rig;
  rig.config.resumeQueuedS = 0;
  rig.stop();
  rig.start();
  rig.camera->delay = 200ms;
  auto first = rig.json(rig.call(http::verb::post, "/api/capture/empty"))["job"];
  auto queued = rig.json(rig.call(http::verb::post, "/api/capture/empty"))["job"];
  rig.stop();
  rig.start();
  EXPECT_EQ(rig.waitJob(first)["state"], "done");
  auto j = rig.waitJob(queued);
  EXPECT_EQ(j["state"], "failed");
  EXPECT_NE(j["error"].get<std::string>().find("cancelled"), std::string::npos) << j.dump();
}

TEST(Station, ReloadAppliesAtOnceAndSwapsTheProcessorOnlyBetweenJobs) {
  Rig rig;
  rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture/empty"))["job"]);
  rig.camera->delay = 300ms;
  auto job = rig.json(rig.call(http::verb::post, "/api/capture"))["job"];
  Config fresh = rig.config;
  fresh.reviewBelowConfidence = 0.99;
  fresh.queueLimit = 1;
  fresh.productShadow = true;
  fresh.cameraDevice = "/dev/video9";  // needs a restart: logged, not applied
  rig.station->reload(fresh);
  rig.runUntil(
      [&] { return rig.json(rig.call(http::verb::get, "/api/status"))["config"]["reloads"] == 1; });
  auto status = rig.json(rig.call(http::verb::get, "/api/status"));
  EXPECT_EQ(status["config"]["queue_limit"], 1);
  EXPECT_EQ(status["config"]["review_below_confidence"], 0.99);
  EXPECT_EQ(status["config"]["product_shadow"], true);
  EXPECT_EQ(status["camera"]["device"], "fake0");
  EXPECT_EQ(rig.processorsMade, 0) << "the processor was swapped under a running job";
  auto j = rig.waitJob(job);
  EXPECT_EQ(j["state"], "done");
  EXPECT_TRUE(rig.runUntil([&] { return rig.processorsMade == 1; }));
  // The new threshold files the next capture (confidence 0.95) for review.
  j = rig.waitJob(rig.json(rig.call(http::verb::post, "/api/capture"))["job"]);
  auto item = rig.json(rig.call(http::verb::get, "/api/items/" + j["item_id"].dump()));
  EXPECT_EQ(item["status"], "needs_review");
}

TEST(Api, BadInputGetsClearErrors) {
  Rig rig;
  EXPECT_EQ(rig.call(http::verb::get, "/api/items/abc").result(), http::status::bad_request);
  EXPECT_EQ(rig.call(http::verb::get, "/api/items/0").result(), http::status::bad_request);
  EXPECT_EQ(rig.call(http::verb::get, "/api/items/999").result(), http::status::not_found);
  EXPECT_EQ(rig.call(http::verb::get, "/api/jobs/999").result(), http::status::not_found);
  EXPECT_EQ(rig.call(http::verb::get, "/api/items/1/images/..").result(), http::status::not_found);
  EXPECT_EQ(rig.call(http::verb::get, "/api/items/../../etc/passwd").result(),
            http::status::not_found);
  EXPECT_EQ(rig.call(http::verb::get, "/api/items/1/images/%2e%2e").result(),
            http::status::not_found);
  EXPECT_EQ(rig.call(http::verb::patch, "/api/items/1", "{not json").result(),
            http::status::bad_request);
  auto unknown = rig.call(http::verb::patch, "/api/items/1", R"({"colour": "red"})");
  EXPECT_EQ(unknown.result(), http::status::bad_request);
  EXPECT_NE(unknown.body().find("colour"), std::string::npos);
  EXPECT_EQ(rig.call(http::verb::post, "/api/capture", R"({"sku": "a/b"})").result(),
            http::status::bad_request);
  EXPECT_EQ(rig.call(http::verb::get, "/api/items?limit=100000").result(),
            http::status::bad_request);
  EXPECT_EQ(rig.call(http::verb::get, "/api/items?type=hat").result(), http::status::bad_request);
  EXPECT_EQ(rig.call(http::verb::put, "/api/status").result(), http::status::method_not_allowed);
  EXPECT_EQ(rig.call(http::verb::get, "/api/nothing").result(), http::status::not_found);
}

TEST(Router, PatternsParamsAndQuery) {
  Router r;
  std::string got;
  r.add(http::verb::get, "/api/items/{id}/pattern.{ext}",
        [&](const Request&, const RouteMatch& m, Reply reply) {
          got = m.param("id") + "|" + m.param("ext") + "|" + m.queryValue("size").value_or("-");
          reply(textResponse(http::status::ok, "text/plain", got));
        });
  auto m = r.find(http::verb::get, "/api/items/12/pattern.dxf?size=5%35&x");
  ASSERT_TRUE(m.handler);
  EXPECT_EQ(m.match.params["ext"], "dxf");
  EXPECT_EQ(m.match.query["size"], "55");
  EXPECT_FALSE(r.find(http::verb::get, "/api/items/12/pattern.").handler);
  EXPECT_FALSE(r.find(http::verb::get, "/api/items/1.2/pattern.dxf").handler);
  EXPECT_FALSE(r.find(http::verb::get, "/api/items/../pattern.dxf").handler);
  EXPECT_TRUE(r.find(http::verb::post, "/api/items/1/pattern.dxf").pathMatched);
  EXPECT_FALSE(r.find(http::verb::get, "").handler);
  RouteMatch rm;
  rm.params["id"] = "99999999999999999999";
  EXPECT_THROW(rm.id("id"), BadRequest);
}

TEST(StaticFiles, OnlyWhitelistedFilesWithTypes) {
  test::TempDir dir;
  std::filesystem::create_directories(dir.path() / "web" / "img");
  std::ofstream(dir.path() / "web" / "index.html") << "<html></html>";
  std::ofstream(dir.path() / "web" / "app.js") << "1";
  std::ofstream(dir.path() / "web" / "img" / "logo.svg") << "<svg/>";
  std::ofstream(dir.path() / "web" / ".secret.html") << "no";
  std::ofstream(dir.path() / "web" / "notes.bak") << "no";
  std::ofstream(dir.path() / "outside.html") << "no";
  StaticFiles files((dir.path() / "web").string());
  EXPECT_EQ(files.fileCount(), 3u);
  auto index = files.serve("/", 11, true);
  ASSERT_TRUE(index);
  EXPECT_EQ((*index)[http::field::content_type], "text/html; charset=utf-8");
  EXPECT_EQ((*files.serve("/app.js", 11, true))[http::field::content_type],
            "text/javascript; charset=utf-8");
  EXPECT_TRUE(files.serve("/img/logo.svg", 11, true));
  EXPECT_FALSE(files.serve("/.secret.html", 11, true));
  EXPECT_FALSE(files.serve("/notes.bak", 11, true));
  EXPECT_FALSE(files.serve("/../outside.html", 11, true));
  EXPECT_FALSE(files.serve("/img/../../outside.html", 11, true));
}

TEST(Naming, TemplateExpandsToOneSafeFileName) {
  EXPECT_EQ(expandNamingTemplate("{sku}_{kind}", {{"sku", "A-1"}, {"kind", "cutout"}}),
            "A-1_cutout");
  EXPECT_EQ(expandNamingTemplate("{sku}/{kind}", {{"sku", "../x"}, {"kind", "a b"}}), "_x_a_b");
  EXPECT_EQ(expandNamingTemplate("", {}), "item");
  EXPECT_EQ(expandNamingTemplate("{unknown}", {}), "_unknown_");
}

TEST(SizeGuide, CsvOfTheStoredGuide) {
  const nlohmann::json g = {
      {"units", "cm"},
      {"type", "top"},
      {"chart", "korean_women"},
      {"base_size", "55"},
      {"measurements", {"bust_circ"}},
      {"rows",
       {{{"size", "44"}, {"garment", {{"bust_circ", 82.0}}}, {"body", nlohmann::json::object()}},
        {{"size", "55"},
         {"garment", {{"bust_circ", 88.25}}},
         {"body", nlohmann::json::object()}}}}};
  EXPECT_EQ(sizeGuideCsv(g), "size,item,bust_circ\r\n44,,82.0\r\n55,yes,88.3\r\n");
  // The old shape is refused with the field named, not read with defaults.
  const nlohmann::json old = {{"sizes", {"44"}}, {"measurements", {{"bust_circ", {{"44", 82.0}}}}}};
  try {
    sizeGuideCsv(old);
    ADD_FAILURE() << "old shape accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("'sizes'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace garmcap::daemon
