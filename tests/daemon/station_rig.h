#pragma once
// A station on a fake camera and a fake processor, with the real API routes, for the daemon's
// unit tests (station_test.cpp, http_session_test.cpp). No sockets; the event loop is run in
// bounded slices by the test.
#include <gtest/gtest.h>

#include <atomic>
#include <boost/asio/io_context.hpp>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "garmcap/capture/camera.h"
#include "garmcap/capture/gpio.h"
#include "garmcap/daemon/api_routes.h"
#include "garmcap/daemon/station.h"
#include "garmcap/drafts/pattern_io.h"
#include "garmcap/drafts/recipes.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/dsw/size_run.h"
#include "test_util.h"

namespace garmcap::daemon::test {

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
    {
      std::lock_guard lock(deliveredMutex);
      const cv::Mat& given = r.shot == capture::Shot::kEmpty ? bareStill : dressedStill;
      if (!given.empty())
        f.bgr = given.clone();
    }
    if (deliverJpeg) {
      // As a UVC camera's MJPEG still: the JPEG it made, and the frame decoded from it. The
      // texture makes the JPEG unlike any PNG of the frame in bytes and size.
      cv::randu(f.bgr, cv::Scalar::all(0), cv::Scalar::all(255));
      std::vector<uchar> jpeg;
      cv::imencode(".jpg", f.bgr, jpeg, {cv::IMWRITE_JPEG_QUALITY, 90});
      f.encoded.assign(jpeg.begin(), jpeg.end());
      f.encodedMediaType = "image/jpeg";
      f.bgr = cv::imdecode(jpeg, cv::IMREAD_COLOR);
      std::lock_guard lock(deliveredMutex);
      delivered.push_back(f.encoded);
    }
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
  std::atomic<bool> deliverJpeg{false};  // stills come as JPEG (capture::Frame::encoded)
  std::mutex deliveredMutex;
  std::vector<std::string> delivered;  // the JPEG of each still, in order
  cv::Mat bareStill, dressedStill;     // if set (under deliveredMutex), the stills taken

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
                           const ProgressFn& progress,
                           std::shared_ptr<const pipeline::CorrectionTable>) override {
    progress("masks", 0.3);
    if (fail)
      throw std::runtime_error("no garment found on the form");
    EXPECT_TRUE(cal.value("fake", false));
    ProcessedCapture r;
    r.type = "skirt";
    r.confidence = confidence;
    r.measurementsCm = {{"waist_circ", 60.0 + dressed.at<cv::Vec3b>(0, 0)[0]}};
    r.warnings = warnings;
    if (undraftable || legacyEmptyPattern) {
      // The draft failed: the pipeline keeps the measurements and says why. Catalogs written
      // before storeBasePattern kept an empty pattern row too.
      r.warnings.push_back("no pattern: recipe 'dress': sleeve of 1.1 cm, shorter than 2 cm");
      const nlohmann::json empty = {{"type", "dress"}, {"panels", nlohmann::json::array()}};
      if (legacyEmptyPattern)
        r.patterns["base"] = empty;
      else
        storeBasePattern(r, empty);
    } else if (gradedDress) {
      // The designed dress (scoop neck, flared skirt, drafted on korean_women 55) and its
      // size run, as the pipeline stores them.
      const auto source =
          drafts::readPatternJson(std::string(GARMCAP_TEST_DATA_DIR) + "/designs/dress_55.json");
      const auto run = dsw::gradeSizeRun(source, drafts::sizeChart("korean_women"));
      EXPECT_TRUE(run) << run.error().message;
      r.patterns["base"] = drafts::patternToJsonValue(source);
      r.baseSize = "55";
      for (std::size_t i = 0; run && i < run->sizes.size(); ++i)
        r.patterns[run->sizes[i]] = drafts::patternToJsonValue(run->patterns[i]);
    } else if (draftedPattern) {
      r.patterns["base"] = drafts::patternToJsonValue(
          drafts::draftGarment("skirt_h", drafts::sizeChart("korean_women").body("55")));
    } else {
      r.patterns["base"] = {{"type", "skirt"},
                            {"panels", nlohmann::json::array({{{"name", "skirt_front"}}})}};
    }
    r.images["cutout"] = cv::Mat(8, 8, CV_8UC4, cv::Scalar(1, 2, 3, 255));
    r.images["product"] = cv::Mat(8, 8, CV_8UC3, cv::Scalar(1, 2, 3));
    r.result = {{"type", "skirt"}};
    if (preEncode) {
      // As the pipeline processor hands them over, encoded already; the cut-out's bytes are a
      // marker (another image's PNG), to tell them from an encoding made by the station.
      auto encoded = pipeline::encodeImageSet({r.images.begin(), r.images.end()});
      for (auto& e : encoded)
        if (e.kind == "cutout")
          e.bytes = preEncodedCutout;
      std::promise<std::vector<pipeline::EncodedImage>> ready;
      ready.set_value(std::move(encoded));
      r.encodedImages = ready.get_future().share();
    }
    return r;
  }
  std::atomic<bool> preEncode{false};
  const std::string preEncodedCutout =
      pipeline::encodePng(cv::Mat(4, 4, CV_8UC4, cv::Scalar(9, 8, 7, 255)));
  std::atomic<bool> fail{false};
  std::atomic<bool> undraftable{false};     // measured, but no pattern could be drafted
  std::atomic<bool> draftedPattern{false};  // a real skirt pattern (markers can be laid)
  std::atomic<bool> gradedDress{false};     // the designed dress and its korean_women run
  std::atomic<bool> legacyEmptyPattern{
      false};  // ... and an empty pattern row stored (old catalogs)
  double confidence = 0.95;
  std::vector<std::string> warnings;  // what the pipeline said (set before the capture)
};

struct Rig {
  test::TempDir dir;
  boost::asio::io_context io;
  std::shared_ptr<std::atomic<int>> stills = std::make_shared<std::atomic<int>>(0);
  FakeCamera* camera = nullptr;
  FakeProcessor* processor = nullptr;
  std::unique_ptr<Station> station;
  Router router;

  Config config;
  int processorsMade = 0;  // by the reload factory

  Rig() {
    config.dataDir = (dir.path() / "data").string();
    config.cameraBackend = "fake";
    config.queueLimit = 4;
    start();
  }
  ~Rig() { stop(); }

  /// A new station (fresh fake camera and processor) on `config`, e.g. after stop() to restart
  /// on the same data folder.
  void start() {
    auto cam = std::make_unique<FakeCamera>(stills);
    camera = cam.get();
    auto proc = std::make_unique<FakeProcessor>();
    processor = proc.get();
    station = std::make_unique<Station>(io, config, std::move(cam), nullptr, std::move(proc));
    station->setProcessorFactory([this](const Config&) {
      ++processorsMade;
      auto p = std::make_unique<FakeProcessor>();
      processor = p.get();
      return p;
    });
    station->start();
    router = Router();
    addApiRoutes(router, *station);
  }
  /// SIGTERM's path: the job in hand finishes, then the station is destroyed.
  void stop() {
    if (!station)
      return;
    bool done = false;
    station->shutdown(5s, [&] { done = true; });
    for (int i = 0; i < 500 && !done; ++i)
      io.run_for(10ms);
    station.reset();
    io.restart();
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

}  // namespace garmcap::daemon::test
