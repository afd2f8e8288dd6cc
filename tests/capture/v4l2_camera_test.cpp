// The V4L2 back end's device-independent logic, run against FakeV4l2Device through the syscall
// seam: format negotiation, buffer bookkeeping, broken-frame dropping, timeouts, UVC controls,
// unplug and reconnection.

#include "garmcap/capture/v4l2_camera.h"

#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <algorithm>
#include <opencv2/imgcodecs.hpp>

#include "garmcap/capture/v4l2_fake_device.h"

namespace garmcap::capture {
namespace {

using std::chrono::milliseconds;

FakeV4l2Config smallUvc() {
  FakeV4l2Config c = defaultFakeUvcConfig("/dev/video0");
  // Small sizes keep the JPEG work in the tests cheap.
  const std::vector<cv::Size> sizes{{320, 240}, {160, 120}, {64, 48}};
  c.formats = {{V4L2_PIX_FMT_MJPEG, sizes}, {V4L2_PIX_FMT_YUYV, sizes}};
  return c;
}

struct Rig {
  FakeV4l2Device* fake = nullptr;
  std::unique_ptr<V4l2Camera> camera;
};

Rig makeRig(FakeV4l2Config config = smallUvc()) {
  auto dev = std::make_unique<FakeV4l2Device>(std::move(config));
  Rig r;
  r.fake = dev.get();
  r.camera = std::make_unique<V4l2Camera>("/dev/video0", std::move(dev));
  return r;
}

CameraConfig smallConfig() {
  CameraConfig c;
  c.stillWidth = 320;
  c.stillHeight = 240;
  c.previewWidth = 160;
  c.previewHeight = 120;
  c.timeout = milliseconds(300);
  c.settleFrames = 2;
  return c;
}

CameraErrorKind kindOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const CameraError& e) {
    return e.kind();
  }
  ADD_FAILURE() << "no CameraError thrown";
  return CameraErrorKind::kIo;
}

// --- format negotiation (pure) ---------------------------------------------------------------

TEST(V4l2Negotiation, AutoPrefersMjpegAndTakesLargestForZero) {
  const std::vector<V4l2FormatOption> offered{
      {V4L2_PIX_FMT_YUYV, {{640, 480}, {1280, 720}}},
      {V4L2_PIX_FMT_MJPEG, {{640, 480}, {1920, 1080}, {1280, 720}}}};
  const auto c = chooseV4l2Format(offered, PixelFormat::kAuto, {0, 0});
  ASSERT_TRUE(c);
  EXPECT_EQ(c->fourcc, V4L2_PIX_FMT_MJPEG);
  EXPECT_EQ(c->size, cv::Size(1920, 1080));
}

TEST(V4l2Negotiation, ExactElseSmallestCoveringElseLargest) {
  const std::vector<V4l2FormatOption> offered{
      {V4L2_PIX_FMT_MJPEG, {{640, 480}, {1920, 1080}, {1280, 720}, {800, 600}}}};
  EXPECT_EQ(chooseV4l2Format(offered, PixelFormat::kAuto, {1280, 720})->size, cv::Size(1280, 720));
  EXPECT_EQ(chooseV4l2Format(offered, PixelFormat::kAuto, {700, 500})->size, cv::Size(800, 600));
  EXPECT_EQ(chooseV4l2Format(offered, PixelFormat::kAuto, {4000, 3000})->size,
            cv::Size(1920, 1080));
}

TEST(V4l2Negotiation, HonoursAnExplicitFormatAndRefusesUndecodableOnes) {
  const std::vector<V4l2FormatOption> offered{{V4L2_PIX_FMT_MJPEG, {{640, 480}}},
                                              {V4L2_PIX_FMT_YUYV, {{320, 240}}}};
  EXPECT_EQ(chooseV4l2Format(offered, PixelFormat::kYuyv, {0, 0})->fourcc, V4L2_PIX_FMT_YUYV);
  EXPECT_FALSE(chooseV4l2Format(offered, PixelFormat::kBgr888, {0, 0}));
  const std::vector<V4l2FormatOption> h264only{{V4L2_PIX_FMT_H264, {{1920, 1080}}}};
  EXPECT_FALSE(chooseV4l2Format(h264only, PixelFormat::kAuto, {0, 0}));
  EXPECT_FALSE(chooseV4l2Format(offered, PixelFormat::kMjpeg, {0, 0}) == std::nullopt);
}

// --- open errors -----------------------------------------------------------------------------

TEST(V4l2Camera, MissingDeviceSaysSoPlainly) {
  auto rig = makeRig();
  rig.fake->setPresent(false);
  try {
    rig.camera->open();
    FAIL() << "open() of a missing device succeeded";
  } catch (const CameraError& e) {
    EXPECT_EQ(e.kind(), CameraErrorKind::kNotFound);
    EXPECT_STREQ(e.what(), "no camera at /dev/video0");
  }
}

TEST(V4l2Camera, RealSystemWithoutDeviceSaysSoToo) {
  V4l2Camera camera("/dev/video-garmcap-does-not-exist");
  try {
    camera.open();
    FAIL();
  } catch (const CameraError& e) {
    EXPECT_EQ(e.kind(), CameraErrorKind::kNotFound);
    EXPECT_STREQ(e.what(), "no camera at /dev/video-garmcap-does-not-exist");
  }
}

TEST(V4l2Camera, BusyDeviceIsReportedAsBusy) {
  auto rig = makeRig();
  rig.fake->setBusy(true);
  EXPECT_EQ(kindOf([&] { rig.camera->open(); }), CameraErrorKind::kBusy);
}

TEST(V4l2Camera, NonCaptureNodeIsRefusedAndClosed) {
  auto config = smallUvc();
  config.videoCapture = false;
  auto rig = makeRig(config);
  EXPECT_EQ(kindOf([&] { rig.camera->open(); }), CameraErrorKind::kUnsupported);
  EXPECT_FALSE(rig.fake->isOpen());
  EXPECT_FALSE(rig.camera->isOpen());
}

TEST(V4l2Camera, NoDecodableFormatIsUnsupportedAndListsWhatIsOffered) {
  auto config = smallUvc();
  config.formats = {{V4L2_PIX_FMT_H264, {{1920, 1080}}}};
  auto rig = makeRig(config);
  rig.camera->open();
  try {
    rig.camera->configure(smallConfig());
    FAIL();
  } catch (const CameraError& e) {
    EXPECT_EQ(e.kind(), CameraErrorKind::kUnsupported);
    EXPECT_NE(std::string(e.what()).find("H264"), std::string::npos) << e.what();
  }
}

// --- streaming -------------------------------------------------------------------------------

TEST(V4l2Camera, StillIsFullSizeBgrAndBuffersAreReleased) {
  auto rig = makeRig();
  rig.camera->open();
  rig.camera->configure(smallConfig());
  const Frame f = rig.camera->captureStill({Shot::kEmpty});
  EXPECT_EQ(f.bgr.size(), cv::Size(320, 240));
  EXPECT_EQ(f.bgr.type(), CV_8UC3);
  EXPECT_EQ(f.meta.pixelFormat, "MJPG");
  EXPECT_EQ(f.meta.backend, "v4l2");
  EXPECT_EQ(f.meta.shot, Shot::kEmpty);
  EXPECT_FALSE(f.meta.preview);
  // Settle frames were thrown away: 2 settle + 1 kept.
  EXPECT_EQ(rig.fake->framesDelivered(), 3u);
  // Without a preview the stream is torn down completely.
  EXPECT_FALSE(rig.fake->streaming());
  EXPECT_EQ(rig.fake->buffersMapped(), 0u);
  EXPECT_EQ(rig.fake->buffersAllocated(), 0u);
  // Red grows to the right in the fake's scene: no channel swap, no mirror.
  EXPECT_GT(f.bgr.at<cv::Vec3b>(120, 300)[2], f.bgr.at<cv::Vec3b>(120, 10)[2] + 150);
}

TEST(V4l2Camera, PreviewStillPreviewSwitchesModesWithoutLeaks) {
  auto rig = makeRig();
  rig.camera->open();
  rig.camera->configure(smallConfig());
  rig.camera->startPreview();
  auto p1 = rig.camera->nextPreviewFrame(milliseconds(200));
  ASSERT_TRUE(p1);
  EXPECT_EQ(p1->bgr.size(), cv::Size(160, 120));
  EXPECT_TRUE(p1->meta.preview);
  EXPECT_EQ(rig.fake->size(), cv::Size(160, 120));

  // The fake refuses S_FMT/REQBUFS while buffers are mapped, so this only passes when the
  // camera unmaps, frees and renegotiates in the right order.
  const Frame still = rig.camera->captureStill();
  EXPECT_EQ(still.bgr.size(), cv::Size(320, 240));
  EXPECT_TRUE(rig.camera->previewRunning());
  EXPECT_TRUE(rig.fake->streaming());
  EXPECT_EQ(rig.fake->size(), cv::Size(160, 120));

  auto p2 = rig.camera->nextPreviewFrame(milliseconds(200));
  ASSERT_TRUE(p2);
  EXPECT_GT(p2->meta.sequence, still.meta.sequence);
  EXPECT_GT(still.meta.sequence, p1->meta.sequence);
  EXPECT_EQ(rig.fake->buffersMapped(), rig.fake->buffersAllocated());

  rig.camera->stopPreview();
  EXPECT_FALSE(rig.fake->streaming());
  EXPECT_EQ(rig.fake->buffersMapped(), 0u);
  rig.camera->close();
  EXPECT_FALSE(rig.fake->isOpen());
  rig.camera->close();  // twice is fine
}

// Issue 16: an MJPEG still carries the camera's own JPEG, which decodes to exactly the frame (the
// station stores it instead of encoding the frame again); preview frames and YUYV stills carry
// none (nothing encoded to keep, or not worth a copy per preview frame).
TEST(V4l2Camera, MjpegStillKeepsTheCamerasJpeg) {
  auto rig = makeRig();
  rig.camera->open();
  rig.camera->configure(smallConfig());
  rig.camera->startPreview();
  auto preview = rig.camera->nextPreviewFrame(milliseconds(200));
  ASSERT_TRUE(preview);
  EXPECT_TRUE(preview->encoded.empty());
  EXPECT_TRUE(preview->encodedMediaType.empty());
  const Frame still = rig.camera->captureStill();
  EXPECT_EQ(still.meta.pixelFormat, "MJPG");
  ASSERT_GT(still.encoded.size(), 4u);
  EXPECT_EQ(still.encodedMediaType, "image/jpeg");
  EXPECT_EQ(still.encoded.substr(0, 2), "\xff\xd8");
  const cv::Mat decoded = cv::imdecode(cv::Mat(1, static_cast<int>(still.encoded.size()), CV_8U,
                                               const_cast<char*>(still.encoded.data())),
                                       cv::IMREAD_COLOR);
  ASSERT_EQ(decoded.size(), still.bgr.size());
  EXPECT_EQ(cv::norm(decoded, still.bgr, cv::NORM_INF), 0.0);

  auto yuyv = makeRig();
  yuyv.camera->open();
  auto config = smallConfig();
  config.pixelFormat = PixelFormat::kYuyv;
  yuyv.camera->configure(config);
  const Frame raw = yuyv.camera->captureStill();
  EXPECT_EQ(raw.meta.pixelFormat, "YUYV");
  EXPECT_TRUE(raw.encoded.empty());
  EXPECT_TRUE(raw.encodedMediaType.empty());
}

TEST(V4l2Camera, YuyvFramesDecodeWithTheRightColours) {
  auto rig = makeRig();
  rig.camera->open();
  auto config = smallConfig();
  config.pixelFormat = PixelFormat::kYuyv;
  rig.camera->configure(config);
  const Frame f = rig.camera->captureStill();
  EXPECT_EQ(f.meta.pixelFormat, "YUYV");
  ASSERT_EQ(f.bgr.size(), cv::Size(320, 240));
  EXPECT_GT(f.bgr.at<cv::Vec3b>(120, 300)[2], f.bgr.at<cv::Vec3b>(120, 10)[2] + 150);
}

TEST(V4l2Camera, BrokenFramesAreDroppedNotDecoded) {
  auto rig = makeRig();
  rig.camera->open();
  auto config = smallConfig();
  config.settleFrames = 0;
  rig.camera->configure(config);
  rig.camera->startPreview();
  rig.fake->injectFrameFaults(FakeFrameFault::kTruncated, 1);
  ASSERT_TRUE(rig.camera->nextPreviewFrame(milliseconds(200)));
  EXPECT_EQ(rig.camera->stats().framesDropped, 1u);
  EXPECT_NE(rig.camera->stats().lastDropReason.find("FFD9"), std::string::npos);

  rig.fake->injectFrameFaults(FakeFrameFault::kNoStart, 1);
  ASSERT_TRUE(rig.camera->nextPreviewFrame(milliseconds(200)));
  EXPECT_NE(rig.camera->stats().lastDropReason.find("FFD8"), std::string::npos);

  rig.fake->injectFrameFaults(FakeFrameFault::kTiny, 1);
  ASSERT_TRUE(rig.camera->nextPreviewFrame(milliseconds(200)));
  EXPECT_NE(rig.camera->stats().lastDropReason.find("too small"), std::string::npos);

  rig.fake->injectFrameFaults(FakeFrameFault::kErrorFlag, 1);
  ASSERT_TRUE(rig.camera->nextPreviewFrame(milliseconds(200)));
  EXPECT_NE(rig.camera->stats().lastDropReason.find("ERROR"), std::string::npos);

  EXPECT_EQ(rig.camera->stats().framesDropped, 4u);
  EXPECT_EQ(rig.camera->stats().framesDecoded, 4u);
}

TEST(V4l2Camera, OnlyBrokenFramesIsATimeoutThatSaysWhy) {
  auto rig = makeRig();
  rig.camera->open();
  auto config = smallConfig();
  config.timeout = milliseconds(60);
  rig.camera->configure(config);
  rig.fake->injectFrameFaults(FakeFrameFault::kTruncated, 1000000);
  try {
    rig.camera->captureStill();
    FAIL();
  } catch (const CameraError& e) {
    EXPECT_EQ(e.kind(), CameraErrorKind::kTimeout);
    EXPECT_NE(std::string(e.what()).find("broken frame"), std::string::npos) << e.what();
  }
  EXPECT_EQ(rig.fake->buffersMapped(), 0u);  // cleaned up after the failure
}

TEST(V4l2Camera, StalledStreamTimesOutWithoutThrowing) {
  auto rig = makeRig();
  rig.camera->open();
  rig.camera->configure(smallConfig());
  rig.camera->startPreview();
  rig.fake->setStalled(true);
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_FALSE(rig.camera->nextPreviewFrame(milliseconds(30)));
  EXPECT_GE(std::chrono::steady_clock::now() - t0, milliseconds(30));
  EXPECT_EQ(rig.camera->stats().timeouts, 1u);
  rig.fake->setStalled(false);
  EXPECT_TRUE(rig.camera->nextPreviewFrame(milliseconds(200)));
}

TEST(V4l2Camera, DrainsToTheNewestFrameAndRequeuesTheOthers) {
  auto rig = makeRig();
  rig.camera->open();
  auto config = smallConfig();
  config.settleFrames = 0;
  rig.camera->configure(config);
  rig.camera->startPreview();
  ASSERT_TRUE(rig.camera->nextPreviewFrame(milliseconds(200)));
  // The application fell behind: three frames wait in the driver.
  ASSERT_EQ(rig.fake->completeFrames(3), 3);
  const auto delivered = rig.fake->framesDelivered();
  auto f = rig.camera->nextPreviewFrame(milliseconds(200));
  ASSERT_TRUE(f);
  EXPECT_EQ(rig.fake->framesPending(), 0u);
  EXPECT_EQ(rig.fake->framesDelivered(), delivered);  // nothing new was needed
  // The newest of the three (fake timestamps are sequence x 33333 µs).
  EXPECT_EQ(f->meta.timestamp,
            std::chrono::microseconds(static_cast<std::int64_t>(delivered - 1) * 33333));
  // Every buffer is back with the driver, so the stream keeps going.
  EXPECT_EQ(rig.fake->completeFrames(10), static_cast<int>(V4l2Camera::kBufferCount));
}

TEST(V4l2Camera, StateErrorsAreClear) {
  auto rig = makeRig();
  EXPECT_EQ(kindOf([&] { rig.camera->captureStill(); }), CameraErrorKind::kState);
  rig.camera->open();
  rig.camera->configure(smallConfig());
  EXPECT_EQ(kindOf([&] { rig.camera->nextPreviewFrame(milliseconds(10)); }),
            CameraErrorKind::kState);
  auto bad = smallConfig();
  bad.stillWidth = -1;
  EXPECT_EQ(kindOf([&] { rig.camera->configure(bad); }), CameraErrorKind::kUnsupported);
}

// --- controls --------------------------------------------------------------------------------

CaptureSettings lockedSettings() {
  CaptureSettings s;
  s.autoExposure = false;
  s.exposureUs = 10000;
  s.analogueGain = 2.0;
  s.autoWhiteBalance = false;
  s.whiteBalanceKelvin = 5200;
  s.autoFocus = false;
  s.focusPosition = 42;
  return s;
}

TEST(V4l2Controls, LockSetsAutoOffBeforeAbsoluteValues) {
  auto rig = makeRig();
  rig.camera->open();
  rig.camera->lockSettings(lockedSettings());
  EXPECT_TRUE(rig.camera->unsupportedSettings().empty());
  EXPECT_EQ(rig.fake->control(V4L2_CID_EXPOSURE_AUTO), V4L2_EXPOSURE_MANUAL);
  EXPECT_EQ(rig.fake->control(V4L2_CID_EXPOSURE_ABSOLUTE), 100);  // 100 µs units
  EXPECT_EQ(rig.fake->control(V4L2_CID_EXPOSURE_AUTO_PRIORITY), 0);
  EXPECT_EQ(rig.fake->control(V4L2_CID_GAIN), 128);  // default 64 x 2
  EXPECT_EQ(rig.fake->control(V4L2_CID_AUTO_WHITE_BALANCE), 0);
  EXPECT_EQ(rig.fake->control(V4L2_CID_WHITE_BALANCE_TEMPERATURE), 5200);
  EXPECT_EQ(rig.fake->control(V4L2_CID_FOCUS_AUTO), 0);
  EXPECT_EQ(rig.fake->control(V4L2_CID_FOCUS_ABSOLUTE), 40);  // aligned to the step of 5
  const auto& w = rig.fake->controlWrites();
  auto pos = [&](std::uint32_t id) { return std::find(w.begin(), w.end(), id) - w.begin(); };
  EXPECT_LT(pos(V4L2_CID_EXPOSURE_AUTO), pos(V4L2_CID_EXPOSURE_ABSOLUTE));
  EXPECT_LT(pos(V4L2_CID_AUTO_WHITE_BALANCE), pos(V4L2_CID_WHITE_BALANCE_TEMPERATURE));
  EXPECT_LT(pos(V4L2_CID_FOCUS_AUTO), pos(V4L2_CID_FOCUS_ABSOLUTE));
}

TEST(V4l2Controls, ValuesAreClampedToTheControlRange) {
  auto rig = makeRig();
  rig.camera->open();
  auto s = lockedSettings();
  s.exposureUs = 10'000'000;  // 10 s: beyond the camera's 2047 x 100 µs
  s.whiteBalanceKelvin = 9000;
  rig.camera->lockSettings(s);
  EXPECT_EQ(rig.fake->control(V4L2_CID_EXPOSURE_ABSOLUTE), 2047);
  EXPECT_EQ(rig.fake->control(V4L2_CID_WHITE_BALANCE_TEMPERATURE), 6500);
}

TEST(V4l2Controls, MissingControlsAreReportedNotFatal) {
  auto config = smallUvc();
  config.controls.erase(V4L2_CID_WHITE_BALANCE_TEMPERATURE);
  config.controls.erase(V4L2_CID_FOCUS_AUTO);
  config.controls.erase(V4L2_CID_FOCUS_ABSOLUTE);
  auto rig = makeRig(config);
  rig.camera->open();
  rig.camera->lockSettings(lockedSettings());
  const auto u = rig.camera->unsupportedSettings();
  EXPECT_NE(std::find(u.begin(), u.end(), "whiteBalanceKelvin"), u.end());
  EXPECT_NE(std::find(u.begin(), u.end(), "autoFocus"), u.end());
  EXPECT_EQ(std::find(u.begin(), u.end(), "exposureUs"), u.end());
}

TEST(V4l2Controls, SettingsGivenBeforeOpenAreAppliedAtOpenAndReported) {
  auto rig = makeRig();
  rig.camera->lockSettings(lockedSettings());
  EXPECT_EQ(rig.fake->controlWrites().size(), 0u);
  rig.camera->open();
  EXPECT_EQ(rig.fake->control(V4L2_CID_EXPOSURE_AUTO), V4L2_EXPOSURE_MANUAL);
  rig.camera->configure(smallConfig());
  const Frame f = rig.camera->captureStill();
  EXPECT_EQ(f.meta.exposureUs, 10000);
  EXPECT_EQ(f.meta.whiteBalanceKelvin, 5200);
}

TEST(V4l2Controls, InvalidSettingsAreRefused) {
  auto rig = makeRig();
  auto s = lockedSettings();
  s.analogueGain = 0.5;
  EXPECT_EQ(kindOf([&] { rig.camera->lockSettings(s); }), CameraErrorKind::kUnsupported);
}

// --- unplug and reconnection -----------------------------------------------------------------

TEST(V4l2Reconnect, UnplugIsDisconnectedAndReconnectRestoresEverything) {
  auto rig = makeRig();
  rig.camera->open();
  rig.camera->configure(smallConfig());
  rig.camera->lockSettings(lockedSettings());
  rig.camera->startPreview();
  ASSERT_TRUE(rig.camera->nextPreviewFrame(milliseconds(200)));

  rig.fake->setPresent(false);
  EXPECT_EQ(kindOf([&] { rig.camera->nextPreviewFrame(milliseconds(100)); }),
            CameraErrorKind::kDisconnected);
  EXPECT_FALSE(rig.camera->reconnect());  // still unplugged
  EXPECT_FALSE(rig.camera->isOpen());
  EXPECT_FALSE(rig.fake->isOpen());

  rig.fake->setPresent(true);
  const auto writesBefore = rig.fake->controlWrites().size();
  ASSERT_TRUE(rig.camera->reconnect());
  EXPECT_EQ(rig.fake->openCount(), 2);
  EXPECT_GT(rig.fake->controlWrites().size(), writesBefore);  // settings re-applied
  EXPECT_TRUE(rig.camera->previewRunning());
  auto f = rig.camera->nextPreviewFrame(milliseconds(200));
  ASSERT_TRUE(f);
  EXPECT_EQ(f->bgr.size(), cv::Size(160, 120));
  EXPECT_EQ(rig.camera->captureStill().bgr.size(), cv::Size(320, 240));
}

TEST(V4l2Reconnect, UnplugDuringStillIsDisconnected) {
  auto rig = makeRig();
  rig.camera->open();
  rig.camera->configure(smallConfig());
  rig.fake->setPresent(false);
  EXPECT_EQ(kindOf([&] { rig.camera->captureStill(); }), CameraErrorKind::kDisconnected);
  rig.fake->setPresent(true);
  ASSERT_TRUE(rig.camera->reconnect());
  EXPECT_EQ(rig.camera->captureStill().bgr.size(), cv::Size(320, 240));
}

}  // namespace
}  // namespace garmcap::capture
