// The station state machine and the API handlers, with a fake camera and a fake processor, no
// sockets: requests go through Router::dispatch, the event loop is run in bounded slices.
#include "garmcap/daemon/station.h"

#include <gtest/gtest.h>

#include <atomic>
#include <boost/asio/io_context.hpp>
#include <fstream>
#include <opencv2/imgproc.hpp>
#include <set>
#include <thread>

#include "garmcap/capture/camera.h"
#include "garmcap/capture/gpio.h"
#include "garmcap/daemon/api_routes.h"
#include "test_util.h"

namespace garmcap::daemon {
namespace {

using namespace std::chrono_literals;

class FakeCamera : public capture::Camera {
 public:
  explicit FakeCamera(std::shared_ptr<std::atomic<int>> stills) : stills_(std::move(stills)) {}
  std::string backend() const override { return "fake"; }
  std::string device() const override { return "fake0"; }
  void open() override {
    if (absent)
      throw capture::CameraError(capture::CameraErrorKind::kNotFound, "no fake0");
    open_ = true;
  }
  void close() noexcept override { open_ = false; }
  bool isOpen() const override { return open_; }
  void configure(const capture::CameraConfig& c) override { config_ = c; }
  capture::CameraConfig config() const override { return config_; }
  cv::Size stillSize() const override { return {64, 48}; }
  cv::Size previewSize() const override { return {32, 24}; }
  void lockSettings(const capture::CaptureSettings&) override {}
  capture::CaptureSettings settings() const override { return {}; }
  std::vector<std::string> unsupportedSettings() const override { return {}; }
  capture::Frame captureStill(const capture::StillRequest& r) override {
    if (absent)
      throw capture::CameraError(capture::CameraErrorKind::kDisconnected, "fake0 went away");
    std::this_thread::sleep_for(delay);
    capture::Frame f;
    const int n = ++*stills_;
    f.bgr = cv::Mat(48, 64, CV_8UC3,
                    r.shot == capture::Shot::kEmpty ? cv::Scalar(0, 200, 0) : cv::Scalar(n, 0, 0));
    return f;
  }
  void startPreview() override {}
  std::optional<capture::Frame> nextPreviewFrame(std::chrono::milliseconds) override {
    return std::nullopt;
  }
  void stopPreview() noexcept override {}
  bool previewRunning() const override { return false; }
  bool reconnect() override { return !absent; }

  std::atomic<bool> absent{false};
  std::chrono::milliseconds delay{0};

 private:
  std::shared_ptr<std::atomic<int>> stills_;
  bool open_ = false;
  capture::CameraConfig config_;
};

class FakeProcessor : public CaptureProcessor {
 public:
  nlohmann::json calibrate(const cv::Mat& empty, const ProgressFn& progress) override {
    progress("registration", 0.5);
    return {{"fake", true}, {"width", empty.cols}};
  }
  ProcessedCapture process(const cv::Mat&, const cv::Mat& dressed, const nlohmann::json& cal,
                           const ProgressFn& progress) override {
    progress("masks", 0.3);
    if (fail)
      throw std::runtime_error("no garment found on the form");
    EXPECT_TRUE(cal.value("fake", false));
    ProcessedCapture r;
    r.type = "skirt";
    r.confidence = confidence;
    r.measurementsCm = {{"waist_circ", 60.0 + dressed.at<cv::Vec3b>(0, 0)[0]}};
    r.patterns["base"] = {{"type", "skirt"}};
    r.images["cutout"] = cv::Mat(8, 8, CV_8UC4, cv::Scalar(1, 2, 3, 255));
    r.result = {{"type", "skirt"}};
    return r;
  }
  std::atomic<bool> fail{false};
  double confidence = 0.95;
};

struct Rig {
  test::TempDir dir;
  boost::asio::io_context io;
  std::shared_ptr<std::atomic<int>> stills = std::make_shared<std::atomic<int>>(0);
  FakeCamera* camera = nullptr;
  FakeProcessor* processor = nullptr;
  std::unique_ptr<Station> station;
  Router router;

  Rig() {
    Config c;
    c.dataDir = (dir.path() / "data").string();
    c.cameraBackend = "fake";
    c.queueLimit = 4;
    auto cam = std::make_unique<FakeCamera>(stills);
    camera = cam.get();
    auto proc = std::make_unique<FakeProcessor>();
    processor = proc.get();
    station = std::make_unique<Station>(io, c, std::move(cam), nullptr, std::move(proc));
    station->start();
    addApiRoutes(router, *station);
  }
  ~Rig() {
    bool done = false;
    station->shutdown(5s, [&] { done = true; });
    for (int i = 0; i < 500 && !done; ++i)
      io.run_for(10ms);
    station.reset();
  }

  /// Runs the loop until `pred` holds (bounded).
  template <typename Pred>
  bool runUntil(Pred pred, std::chrono::milliseconds limit = 5000ms) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < end) {
      io.run_for(5ms);
      if (pred())
        return true;
    }
    return false;
  }

  Response call(http::verb verb, const std::string& target, const std::string& body = "") {
    Request req{verb, target, 11};
    req.body() = body;
    req.prepare_payload();
    std::optional<Response> out;
    router.dispatch(req, [&](Response r) { out = std::move(r); });
    runUntil([&] { return out.has_value(); });
    if (!out)
      ADD_FAILURE() << "no reply for " << target;
    return out ? *out : Response{};
  }
  nlohmann::json json(const Response& r) { return nlohmann::json::parse(r.body()); }

  nlohmann::json waitJob(std::int64_t id) {
    nlohmann::json j;
    runUntil([&] {
      j = json(call(http::verb::get, "/api/jobs/" + std::to_string(id)));
      return j["state"] == "done" || j["state"] == "failed";
    });
    return j;
  }
};

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
  auto pj = rig.call(http::verb::get, "/api/items/" + std::to_string(itemId) + "/pattern.json");
  EXPECT_EQ(rig.json(pj)["type"], "skirt");
  auto list = rig.json(rig.call(http::verb::get, "/api/items?type=skirt"));
  EXPECT_EQ(list["total"], 1);
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

TEST(SizeGuide, Csv) {
  nlohmann::json g = {{"sizes", {"44", "55"}},
                      {"measurements", {{"bust_circ", {{"44", 82.0}, {"55", 88.25}}}}}};
  EXPECT_EQ(sizeGuideCsv(g), "measurement,44,55\nbust_circ,82.0,88.2\n");
}

}  // namespace
}  // namespace garmcap::daemon
