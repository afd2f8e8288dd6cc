// One suite of Camera interface tests run against every back end: the V4L2 logic over the fake
// device, replay over a temporary rig, and — when present — a real V4L2 camera at /dev/video0
// and a real libcamera camera (hardware: GTEST_SKIP without the device; set
// GARMCAP_REQUIRE_HW=1 on a hardware rig to turn those skips into failures).

#include <gtest/gtest.h>
#include <linux/videodev2.h>
#include <unistd.h>

#include <cstdlib>
#include <functional>

#include "garmcap/capture/camera.h"
#include "garmcap/capture/libcamera_camera.h"
#include "garmcap/capture/replay_camera.h"
#include "garmcap/capture/v4l2_camera.h"
#include "garmcap/capture/v4l2_fake_device.h"
#include "garmcap/sim/synthetic_camera.h"
#include "replay_test_rig.h"

namespace garmcap::capture {
namespace {

using std::chrono::milliseconds;

struct Subject {
  std::unique_ptr<Camera> camera;
  std::function<void()> unplug;  // empty for real hardware
  std::function<void()> replug;
  std::shared_ptr<void> keepAlive;
};

struct Backend {
  std::string name;
  /// Returns nullopt (and a reason) when the back end's device is absent.
  std::function<std::optional<Subject>(std::string& whyNot)> make;
};

std::optional<Subject> fakeV4l2(std::string&) {
  FakeV4l2Config c = defaultFakeUvcConfig("/dev/video0");
  const std::vector<cv::Size> sizes{{320, 240}, {160, 120}};
  c.formats = {{V4L2_PIX_FMT_MJPEG, sizes}, {V4L2_PIX_FMT_YUYV, sizes}};
  auto dev = std::make_unique<FakeV4l2Device>(c);
  FakeV4l2Device* fake = dev.get();
  Subject s;
  s.camera = std::make_unique<V4l2Camera>("/dev/video0", std::move(dev));
  s.unplug = [fake] { fake->setPresent(false); };
  s.replug = [fake] { fake->setPresent(true); };
  return s;
}

std::optional<Subject> replay(std::string&) {
  auto rig = std::make_shared<TempRig>("iface");
  rig->make(2, {320, 240});
  auto cam = std::make_unique<ReplayCamera>(makeRigSceneSource(rig->dir));
  ReplayCamera* raw = cam.get();
  Subject s;
  s.camera = std::move(cam);
  s.unplug = [raw] { raw->unplug(); };
  s.replug = [raw] { raw->replug(); };
  s.keepAlive = rig;
  return s;
}

// The synthetic camera is the simulator's (garmcap::sim), made by sim::makeCamera; it must
// behave like every other back end towards the station.
std::optional<Subject> synthetic(std::string&) {
  CameraOptions o = cameraOptions("synthetic");
  o.formPath = std::string(GARMCAP_SHARED_DIR) + "/data/forms/garmentcode_mean_female/form.json";
  o.seed = 11;
  o.syntheticSize = {240, 320};  // small: the renderer's cost grows with the pixels
  std::unique_ptr<Camera> cam = sim::makeCamera(o);
  auto* raw = dynamic_cast<ReplayCamera*>(cam.get());
  Subject s;
  s.camera = std::move(cam);
  s.unplug = [raw] { raw->unplug(); };
  s.replug = [raw] { raw->replug(); };
  return s;
}

std::optional<Subject> realV4l2(std::string& whyNot) {
  if (::access("/dev/video0", F_OK) != 0) {
    whyNot = "no camera at /dev/video0";
    return std::nullopt;
  }
  Subject s;
  s.camera = makeCamera(cameraOptions("v4l2", "/dev/video0"));
  return s;
}

std::optional<Subject> realLibcamera(std::string& whyNot) {
  if (listLibcameraCameras().empty()) {
    whyNot = "no libcamera camera found";
    return std::nullopt;
  }
  Subject s;
  s.camera = makeCamera(cameraOptions("libcamera"));
  return s;
}

void PrintTo(const Backend& b, std::ostream* os) {
  *os << b.name;
}

class CameraInterface : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override {
    std::string whyNot;
    auto s = GetParam().make(whyNot);
    if (!s) {
      const char* require = std::getenv("GARMCAP_REQUIRE_HW");
      if (require != nullptr && std::string(require) == "1") {
        FAIL() << GetParam().name << ": " << whyNot << " (GARMCAP_REQUIRE_HW=1)";
      }
      GTEST_SKIP() << GetParam().name << ": " << whyNot;
    }
    subject_ = std::move(*s);
    cam_ = subject_.camera.get();
  }

  void openAndConfigure() {
    cam_->open();
    CameraConfig c;
    c.stillWidth = 320;
    c.stillHeight = 240;
    c.previewWidth = 160;
    c.previewHeight = 120;
    c.timeout = milliseconds(3000);
    c.settleFrames = 1;
    cam_->configure(c);
  }

  static CameraErrorKind kindOf(const std::function<void()>& f) {
    try {
      f();
    } catch (const CameraError& e) {
      return e.kind();
    }
    ADD_FAILURE() << "no CameraError";
    return CameraErrorKind::kIo;
  }

  Subject subject_;
  Camera* cam_ = nullptr;
};

TEST_P(CameraInterface, StillIsOwnedContinuousBgrOfTheReportedSize) {
  openAndConfigure();
  const Frame f = cam_->captureStill();
  ASSERT_FALSE(f.bgr.empty());
  EXPECT_EQ(f.bgr.type(), CV_8UC3);
  EXPECT_TRUE(f.bgr.isContinuous());
  EXPECT_EQ(f.bgr.size(), cam_->stillSize());
  EXPECT_EQ(f.meta.backend, cam_->backend());
  EXPECT_FALSE(f.meta.preview);
  EXPECT_FALSE(f.meta.pixelFormat.empty());
}

TEST_P(CameraInterface, PreviewFramesAreSmallerAndInSequence) {
  openAndConfigure();
  cam_->startPreview();
  EXPECT_TRUE(cam_->previewRunning());
  std::optional<std::uint64_t> last;
  for (int i = 0; i < 3; ++i) {
    auto f = cam_->nextPreviewFrame(milliseconds(3000));
    ASSERT_TRUE(f) << "no preview frame " << i;
    EXPECT_TRUE(f->meta.preview);
    EXPECT_LE(f->bgr.cols, 160);
    EXPECT_LE(f->bgr.rows, 120);
    if (last) {
      EXPECT_GT(f->meta.sequence, *last);
    }
    last = f->meta.sequence;
  }
  cam_->stopPreview();
  EXPECT_FALSE(cam_->previewRunning());
}

TEST_P(CameraInterface, StillDuringPreviewKeepsThePreviewGoing) {
  openAndConfigure();
  cam_->startPreview();
  ASSERT_TRUE(cam_->nextPreviewFrame(milliseconds(3000)));
  const Frame still = cam_->captureStill();
  EXPECT_EQ(still.bgr.size(), cam_->stillSize());
  EXPECT_TRUE(cam_->previewRunning());
  auto after = cam_->nextPreviewFrame(milliseconds(3000));
  ASSERT_TRUE(after);
  EXPECT_LE(after->bgr.cols, 160);
}

TEST_P(CameraInterface, LockedSettingsStickAndEmptyAndDressedPair) {
  openAndConfigure();
  CaptureSettings s;
  s.autoExposure = false;
  s.exposureUs = 8000;
  s.autoWhiteBalance = false;
  s.whiteBalanceKelvin = 5000;
  s.autoFocus = false;
  cam_->lockSettings(s);
  EXPECT_TRUE(cam_->settings().locked());
  EXPECT_EQ(cam_->settings().exposureUs, 8000);
  const Frame empty = cam_->captureStill({Shot::kEmpty});
  const Frame dressed = cam_->captureStill({Shot::kDressed});
  EXPECT_NO_THROW(requireSameSize(empty.bgr, dressed.bgr, GetParam().name));
  EXPECT_EQ(empty.meta.shot, Shot::kEmpty);
  EXPECT_EQ(dressed.meta.shot, Shot::kDressed);
}

TEST_P(CameraInterface, CallsOutOfOrderAreStateErrors) {
  EXPECT_FALSE(cam_->isOpen());
  EXPECT_EQ(kindOf([&] { cam_->captureStill(); }), CameraErrorKind::kState);
  openAndConfigure();
  EXPECT_EQ(kindOf([&] { cam_->nextPreviewFrame(milliseconds(10)); }), CameraErrorKind::kState);
}

TEST_P(CameraInterface, CloseIsIdempotentAndReopenWorks) {
  openAndConfigure();
  cam_->startPreview();
  cam_->close();
  cam_->close();
  EXPECT_FALSE(cam_->isOpen());
  EXPECT_FALSE(cam_->previewRunning());
  openAndConfigure();
  EXPECT_FALSE(cam_->captureStill().bgr.empty());
}

TEST_P(CameraInterface, UnplugIsDisconnectedAndReconnectRecovers) {
  if (!subject_.unplug) {
    GTEST_SKIP() << "cannot unplug real hardware from a test";
  }
  openAndConfigure();
  cam_->startPreview();
  ASSERT_TRUE(cam_->nextPreviewFrame(milliseconds(3000)));
  subject_.unplug();
  EXPECT_EQ(kindOf([&] { cam_->nextPreviewFrame(milliseconds(100)); }),
            CameraErrorKind::kDisconnected);
  EXPECT_FALSE(cam_->reconnect());
  EXPECT_EQ(kindOf([&] { cam_->open(); }), CameraErrorKind::kNotFound);
  subject_.replug();
  ASSERT_TRUE(cam_->reconnect());
  EXPECT_TRUE(cam_->isOpen());
  EXPECT_TRUE(cam_->nextPreviewFrame(milliseconds(3000)));
  EXPECT_EQ(cam_->captureStill().bgr.size(), cam_->stillSize());
}

INSTANTIATE_TEST_SUITE_P(
    Backends, CameraInterface,
    ::testing::Values(Backend{"v4l2_fake", fakeV4l2}, Backend{"replay", replay},
                      Backend{"synthetic", synthetic}, Backend{"v4l2_hw", realV4l2},
                      Backend{"libcamera_hw", realLibcamera}),
    [](const ::testing::TestParamInfo<Backend>& info) { return info.param.name; });

TEST(CameraFactory, SyntheticWithoutAFormSaysSo) {
  std::unique_ptr<Camera> cam = sim::makeCamera(cameraOptions("synthetic"));
  EXPECT_EQ(cam->backend(), "synthetic");
  try {
    cam->open();
    FAIL();
  } catch (const CameraError& e) {
    EXPECT_EQ(e.kind(), CameraErrorKind::kNotFound);
    EXPECT_NE(std::string(e.what()).find("no dress form"), std::string::npos) << e.what();
  }
}

TEST(CameraFactory, NamesAndPixelFormats) {
  EXPECT_EQ(cameraBackends(), (std::vector<std::string>{"libcamera", "v4l2", "replay"}));
  EXPECT_EQ(makeCamera(cameraOptions("v4l2"))->device(), "/dev/video0");
  EXPECT_EQ(parsePixelFormat("MJPEG"), PixelFormat::kMjpeg);
  EXPECT_EQ(parsePixelFormat("yuyv"), PixelFormat::kYuyv);
  EXPECT_THROW(parsePixelFormat("h264"), std::invalid_argument);
}

// capture does not link the simulator: its factory refuses "synthetic" and says who makes it.
TEST(CameraFactory, CaptureRefersSyntheticToTheSimulator) {
  try {
    makeCamera(cameraOptions("synthetic"));
    FAIL() << "capture::makeCamera made a synthetic camera";
  } catch (const CameraError& e) {
    EXPECT_EQ(e.kind(), CameraErrorKind::kNotAvailable);
    EXPECT_NE(std::string(e.what()).find("sim::makeCamera"), std::string::npos) << e.what();
  }
}

// sim::makeCamera adds "synthetic" and hands every other back end to capture::makeCamera.
TEST(CameraFactory, SimulatorFactoryAddsSyntheticAndForwardsTheRest) {
  EXPECT_EQ(sim::cameraBackends(),
            (std::vector<std::string>{"libcamera", "v4l2", "replay", "synthetic"}));
  const auto v4l2 = sim::makeCamera(cameraOptions("v4l2"));
  EXPECT_EQ(v4l2->backend(), "v4l2");
  EXPECT_EQ(v4l2->device(), "/dev/video0");
  EXPECT_THROW(sim::makeCamera(cameraOptions("replay")), std::invalid_argument);  // no rig folder
  try {
    sim::makeCamera(cameraOptions("webcam"));
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("known: libcamera, v4l2, replay, synthetic)"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace garmcap::capture
