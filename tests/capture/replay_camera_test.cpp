// Replay back end: rig index, case sequencing, PNG and JPEG cases, bad rig data (missing,
// doubled, corrupt and truncated images named, mismatched pair sizes refused), and injected
// faults (latency, corrupt frame, unplug).

#include "garmcap/capture/replay_camera.h"

#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "replay_test_rig.h"

namespace garmcap::capture {
namespace {

using std::chrono::milliseconds;
namespace fs = std::filesystem;

std::unique_ptr<ReplayCamera> openCamera(const fs::path& rig, bool loop = true) {
  auto cam = std::make_unique<ReplayCamera>(makeRigSceneSource(rig), "replay", loop);
  cam->open();
  CameraConfig c;
  c.previewWidth = 80;
  c.previewHeight = 80;
  c.timeout = milliseconds(500);
  cam->configure(c);
  return cam;
}

std::string errorOf(const std::function<void()>& f, CameraErrorKind* kind = nullptr) {
  try {
    f();
  } catch (const CameraError& e) {
    if (kind != nullptr) {
      *kind = e.kind();
    }
    return e.what();
  } catch (const std::exception& e) {
    return std::string("other exception: ") + e.what();
  }
  return "no error";
}

TEST(ReplayCamera, ServesEmptyThenDressedThenNextCase) {
  TempRig rig("seq");
  rig.make(3, {120, 90});
  auto cam = openCamera(rig.dir);
  EXPECT_EQ(cam->caseCount(), 3u);
  const Frame e0 = cam->captureStill();
  const Frame d0 = cam->captureStill();
  const Frame e1 = cam->captureStill({Shot::kEmpty});
  EXPECT_EQ(e0.meta.caseId, "case_000");
  EXPECT_EQ(e0.meta.shot, Shot::kEmpty);
  EXPECT_EQ(d0.meta.caseId, "case_000");
  EXPECT_EQ(d0.meta.shot, Shot::kDressed);
  EXPECT_EQ(e1.meta.caseId, "case_001");
  EXPECT_EQ(e0.meta.truthPath, rig.dir / "case_000" / "truth.json");
  EXPECT_EQ(e0.bgr.size(), cv::Size(120, 90));
  // The pixels are the files' pixels.
  const cv::Mat fileDressed = cv::imread((rig.dir / "case_000" / "dressed.png").string());
  EXPECT_EQ(cv::norm(d0.bgr, fileDressed, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(d0.bgr, e0.bgr, cv::NORM_L1), 0.0);
  EXPECT_LT(e0.meta.sequence, d0.meta.sequence);
}

TEST(ReplayCamera, SelectsCasesByIdAndLoops) {
  TempRig rig("select");
  rig.make(2, {64, 48});
  auto cam = openCamera(rig.dir);
  const Frame d = cam->captureStill({Shot::kDressed, "case_001"});
  EXPECT_EQ(d.meta.caseId, "case_001");
  EXPECT_EQ(cam->currentCase(), 0u);  // wrapped around after the last dressed frame
  CameraErrorKind kind{};
  const std::string msg = errorOf([&] { cam->selectCase("case_999"); }, &kind);
  EXPECT_EQ(kind, CameraErrorKind::kNotFound);
  EXPECT_NE(msg.find("case_999"), std::string::npos);
  EXPECT_NE(msg.find("case_000"), std::string::npos) << "lists known cases: " << msg;
}

TEST(ReplayCamera, WithoutLoopingTheRigRunsOut) {
  TempRig rig("noloop");
  rig.make(1, {64, 48});
  auto cam = openCamera(rig.dir, /*loop=*/false);
  cam->captureStill({Shot::kEmpty});
  cam->captureStill({Shot::kDressed});
  CameraErrorKind kind{};
  EXPECT_NE(errorOf([&] { cam->captureStill(); }, &kind).find("all 1 cases served"),
            std::string::npos);
  EXPECT_EQ(kind, CameraErrorKind::kNotFound);
}

TEST(ReplayCamera, MissingImageNamesTheFile) {
  TempRig rig("missing");
  rig.make(2, {64, 48});
  auto cam = openCamera(rig.dir);
  // Gone after the camera was opened (at open, readRig already refuses the rig: see below).
  fs::remove(rig.dir / "case_001" / "dressed.png");
  cam->selectCase("case_001");
  CameraErrorKind kind{};
  // Even the empty frame is refused: its pair cannot be checked.
  const std::string msg = errorOf([&] { cam->captureStill({Shot::kDressed}); }, &kind);
  EXPECT_EQ(kind, CameraErrorKind::kBadData);
  EXPECT_NE(msg.find((rig.dir / "case_001" / "dressed.png").string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("missing"), std::string::npos) << msg;
  // Missing before opening: the rig is refused at open, naming the file.
  ReplayCamera again(makeRigSceneSource(rig.dir));
  const std::string atOpen = errorOf([&] { again.open(); }, &kind);
  EXPECT_EQ(kind, CameraErrorKind::kBadData);
  EXPECT_NE(atOpen.find((rig.dir / "case_001" / "dressed.png").string()), std::string::npos)
      << atOpen;
  EXPECT_NE(atOpen.find("missing"), std::string::npos) << atOpen;
}

TEST(ReplayCamera, CorruptImageNamesTheFile) {
  TempRig rig("corrupt");
  rig.make(1, {64, 48});
  const fs::path bad = rig.dir / "case_000" / "empty.png";
  std::ofstream(bad, std::ios::binary | std::ios::trunc) << "\x89PNG\r\n\x1a\n garbage";
  auto cam = openCamera(rig.dir);
  CameraErrorKind kind{};
  const std::string msg = errorOf([&] { cam->captureStill({Shot::kEmpty}); }, &kind);
  EXPECT_EQ(kind, CameraErrorKind::kBadData);
  EXPECT_NE(msg.find(bad.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("corrupt"), std::string::npos) << msg;
}

// For PNG and JPEG cases alike (a JPEG pair's sizes come from the JPEG headers).
TEST(ReplayCamera, EmptyAndDressedOfDifferentSizesAreRefused) {
  for (const std::string format : {"png", "jpg"}) {
    TempRig rig("sizes_" + format);
    rig.make(1, {64, 48}, format);
    cv::imwrite((rig.dir / "case_000" / ("dressed." + format)).string(),
                cv::Mat(50, 64, CV_8UC3, cv::Scalar(1, 2, 3)));
    auto cam = openCamera(rig.dir);
    for (Shot shot : {Shot::kEmpty, Shot::kDressed}) {
      CameraErrorKind kind{};
      const std::string msg = errorOf([&] { cam->captureStill({shot}); }, &kind);
      EXPECT_EQ(kind, CameraErrorKind::kBadData) << format << ": " << msg;
      EXPECT_NE(msg.find("64x48"), std::string::npos) << msg;
      EXPECT_NE(msg.find("64x50"), std::string::npos) << msg;
      EXPECT_NE(msg.find("case_000"), std::string::npos) << msg;
    }
  }
}

// JPEG cases (empty.jpg, dressed.jpg) are served like PNG ones; a truncated JPEG and a frame
// present in both formats are refused.
TEST(ReplayCamera, ServesJpegCases) {
  TempRig rig("jpeg");
  rig.make(2, {120, 90}, "jpg");
  auto cam = openCamera(rig.dir);
  const Frame e0 = cam->captureStill();
  const Frame d0 = cam->captureStill();
  EXPECT_EQ(d0.meta.caseId, "case_000");
  EXPECT_EQ(d0.bgr.size(), cv::Size(120, 90));
  const cv::Mat fileDressed = cv::imread((rig.dir / "case_000" / "dressed.jpg").string());
  EXPECT_EQ(cv::norm(d0.bgr, fileDressed, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(d0.bgr, e0.bgr, cv::NORM_L1), 0.0);
}

// Issue 16: a replayed still comes with its file's bytes, as a camera's own JPEG would (the
// station stores them as they are); they decode to exactly the frame. A still scaled to a
// configured size is no longer the file, so it comes without.
TEST(ReplayCamera, StillsCarryTheFileAsDelivered) {
  for (const std::string ext : {"png", "jpg"}) {
    TempRig rig("encoded_" + ext);
    rig.make(1, {120, 90}, ext);
    auto cam = openCamera(rig.dir);
    const Frame e0 = cam->captureStill({Shot::kEmpty});
    const Frame d0 = cam->captureStill({Shot::kDressed});
    std::ifstream in(rig.dir / "case_000" / ("dressed." + ext), std::ios::binary);
    const std::string file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_FALSE(file.empty());
    EXPECT_TRUE(d0.encoded == file) << ext;
    EXPECT_EQ(d0.encodedMediaType, ext == "png" ? "image/png" : "image/jpeg");
    EXPECT_EQ(e0.encodedMediaType, d0.encodedMediaType);
    EXPECT_FALSE(e0.encoded == d0.encoded);
    const cv::Mat decoded = cv::imdecode(cv::Mat(1, static_cast<int>(d0.encoded.size()), CV_8U,
                                                 const_cast<char*>(d0.encoded.data())),
                                         cv::IMREAD_COLOR);
    ASSERT_EQ(decoded.size(), d0.bgr.size()) << ext;
    EXPECT_EQ(cv::norm(decoded, d0.bgr, cv::NORM_INF), 0.0) << ext;
    // The preview shows the last shot, without its file.
    cam->startPreview();
    const auto preview = cam->nextPreviewFrame(milliseconds(100));
    ASSERT_TRUE(preview);
    EXPECT_TRUE(preview->encoded.empty());

    CameraConfig c = cam->config();
    c.stillWidth = 60;
    c.stillHeight = 45;
    cam->configure(c);
    const Frame scaled = cam->captureStill({Shot::kDressed});
    EXPECT_EQ(scaled.bgr.size(), cv::Size(60, 45));
    EXPECT_TRUE(scaled.encoded.empty()) << ext;
    EXPECT_TRUE(scaled.encodedMediaType.empty()) << ext;
  }
}

TEST(ReplayCamera, TruncatedJpegNamesTheFile) {
  TempRig rig("jpeg_cut");
  rig.make(1, {64, 48}, "jpg");
  const fs::path cut = rig.dir / "case_000" / "dressed.jpg";
  fs::resize_file(cut, fs::file_size(cut) - 10);
  auto cam = openCamera(rig.dir);
  // The empty frame is served: the pair's sizes are checked from the headers, which the cut
  // file still has. The dressed frame is refused, named.
  EXPECT_EQ(cam->captureStill({Shot::kEmpty}).bgr.size(), cv::Size(64, 48));
  CameraErrorKind kind{};
  const std::string msg = errorOf([&] { cam->captureStill({Shot::kDressed}); }, &kind);
  EXPECT_EQ(kind, CameraErrorKind::kBadData);
  EXPECT_NE(msg.find(cut.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("truncated JPEG"), std::string::npos) << msg;
}

TEST(ReplayCamera, FrameInBothFormatsNamesTheFiles) {
  TempRig rig("both");
  rig.make(1, {64, 48});
  auto cam = openCamera(rig.dir);
  cv::imwrite((rig.dir / "case_000" / "empty.jpg").string(),
              cv::Mat(48, 64, CV_8UC3, cv::Scalar(1, 2, 3)));
  CameraErrorKind kind{};
  const std::string msg = errorOf([&] { cam->captureStill({Shot::kEmpty}); }, &kind);
  EXPECT_EQ(kind, CameraErrorKind::kBadData);
  EXPECT_NE(msg.find((rig.dir / "case_000" / "empty.png").string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("empty.jpg"), std::string::npos) << msg;
  EXPECT_NE(msg.find("both present"), std::string::npos) << msg;
  ReplayCamera again(makeRigSceneSource(rig.dir));
  const std::string atOpen = errorOf([&] { again.open(); }, &kind);
  EXPECT_EQ(kind, CameraErrorKind::kBadData);
  EXPECT_NE(atOpen.find("both present"), std::string::npos) << atOpen;
}

TEST(ReplayCamera, MissingRigFolderOrIndex) {
  TempRig rig("absent");
  ReplayCamera cam(makeRigSceneSource(rig.dir));
  CameraErrorKind kind{};
  EXPECT_NE(errorOf([&] { cam.open(); }, &kind).find("no rig folder at " + rig.dir.string()),
            std::string::npos);
  EXPECT_EQ(kind, CameraErrorKind::kNotFound);
  fs::create_directories(rig.dir);
  EXPECT_NE(errorOf([&] { cam.open(); }, &kind).find("rig.json"), std::string::npos);
  std::ofstream(rig.dir / "rig.json") << "{\"cases\": [}";
  const std::string msg = errorOf([&] { cam.open(); }, &kind);
  EXPECT_EQ(kind, CameraErrorKind::kBadData);
  EXPECT_NE(msg.find("rig.json"), std::string::npos) << msg;
  EXPECT_NE(msg.find("line 1"), std::string::npos) << msg;
}

TEST(ReplayFaults, LatencyDelaysFramesAndBeyondTheTimeoutTimesOut) {
  TempRig rig("latency");
  rig.make(1, {64, 48});
  auto cam = openCamera(rig.dir);
  cam->setLatency(milliseconds(40));
  auto t0 = std::chrono::steady_clock::now();
  cam->captureStill();
  EXPECT_GE(std::chrono::steady_clock::now() - t0, milliseconds(40));

  CameraConfig c = cam->config();
  c.timeout = milliseconds(20);
  cam->configure(c);
  CameraErrorKind kind{};
  errorOf([&] { cam->captureStill(); }, &kind);
  EXPECT_EQ(kind, CameraErrorKind::kTimeout);
  cam->startPreview();
  EXPECT_FALSE(cam->nextPreviewFrame(milliseconds(10)));
  cam->setLatency(milliseconds(0));
  EXPECT_TRUE(cam->nextPreviewFrame(milliseconds(10)));
}

TEST(ReplayFaults, CorruptFrameFailsTheStillAndIsDroppedFromPreview) {
  TempRig rig("corruptframe");
  rig.make(1, {64, 48});
  auto cam = openCamera(rig.dir);
  cam->injectCorruptFrames(1);
  CameraErrorKind kind{};
  EXPECT_NE(errorOf([&] { cam->captureStill(); }, &kind).find("corrupt"), std::string::npos);
  EXPECT_EQ(kind, CameraErrorKind::kBadData);
  EXPECT_EQ(cam->captureStill().meta.shot, Shot::kEmpty);  // the next one is fine
  cam->startPreview();
  cam->injectCorruptFrames(1);
  EXPECT_FALSE(cam->nextPreviewFrame(milliseconds(10)));
  EXPECT_TRUE(cam->nextPreviewFrame(milliseconds(10)));
  EXPECT_EQ(cam->framesDropped(), 2u);
}

TEST(ReplayFaults, PreviewIsScaledAndFollowsTheLastShot) {
  TempRig rig("preview");
  rig.make(1, {160, 120});
  auto cam = openCamera(rig.dir);
  cam->startPreview();
  auto p = cam->nextPreviewFrame(milliseconds(10));
  ASSERT_TRUE(p);
  EXPECT_EQ(p->bgr.size(), cv::Size(80, 60));  // fits 80x80, keeps 4:3
  EXPECT_EQ(p->meta.caseId, "case_000");
  EXPECT_TRUE(p->meta.preview);
  const Frame dressed = cam->captureStill({Shot::kDressed});
  auto q = cam->nextPreviewFrame(milliseconds(10));
  ASSERT_TRUE(q);
  cv::Mat small;
  cv::resize(dressed.bgr, small, {80, 60}, 0, 0, cv::INTER_AREA);
  EXPECT_EQ(cv::norm(q->bgr, small, cv::NORM_INF), 0.0);
}

TEST(ReplayFaults, ConfiguredStillSizeResizes) {
  TempRig rig("resize");
  rig.make(1, {160, 120});
  auto cam = openCamera(rig.dir);
  CameraConfig c = cam->config();
  c.stillWidth = 80;
  c.stillHeight = 60;
  cam->configure(c);
  EXPECT_EQ(cam->captureStill().bgr.size(), cv::Size(80, 60));
  EXPECT_EQ(cam->stillSize(), cv::Size(80, 60));
  c.pixelFormat = PixelFormat::kMjpeg;
  CameraErrorKind kind{};
  errorOf([&] { cam->configure(c); }, &kind);
  EXPECT_EQ(kind, CameraErrorKind::kUnsupported);
}

TEST(ReplayFactory, MakeCameraBuildsReplayAndRejectsUnknownNames) {
  TempRig rig("factory");
  rig.make(1, {64, 48});
  auto cam = makeCamera(cameraOptions("replay", rig.dir.string()));
  EXPECT_EQ(cam->backend(), "replay");
  cam->open();
  EXPECT_EQ(cam->captureStill().bgr.size(), cv::Size(64, 48));
  try {
    makeCamera(cameraOptions("webcam"));
    FAIL();
  } catch (const std::invalid_argument& e) {
    // capture's own back ends only: "synthetic" is the simulator's (sim::makeCamera).
    EXPECT_NE(std::string(e.what()).find("known: libcamera, v4l2, replay)"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(makeCamera(cameraOptions("replay")), std::invalid_argument);
}

}  // namespace
}  // namespace garmcap::capture
