// libcamera back end: the device-independent parts (control plan, size choice, pixel-format
// conversion) and the no-camera path. Streaming itself runs in the interface suite when a
// libcamera camera is present.

#include <gtest/gtest.h>

#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "garmcap/capture/libcamera_camera.h"
#include "garmcap/capture/v4l2_decode.h"

namespace garmcap::capture {
namespace {

TEST(LibcameraControls, LockedSettingsDisableTheAlgorithmsAndFixTheValues) {
  CaptureSettings s;
  s.autoExposure = false;
  s.exposureUs = 12000;
  s.analogueGain = 1.5;
  s.autoWhiteBalance = false;
  s.redGain = 1.8;
  s.blueGain = 1.4;
  s.autoFocus = false;
  s.focusPosition = 250;
  const auto p = planLibcameraControls(s);
  EXPECT_EQ(p.aeEnable, false);
  EXPECT_EQ(p.exposureTimeUs, 12000);
  EXPECT_FLOAT_EQ(*p.analogueGain, 1.5f);
  EXPECT_EQ(p.awbEnable, false);
  EXPECT_FLOAT_EQ(*p.redGain, 1.8f);
  EXPECT_FLOAT_EQ(*p.blueGain, 1.4f);
  EXPECT_EQ(p.afMode, 0);
  EXPECT_FLOAT_EQ(*p.lensPositionDioptres, 2.5f);
}

TEST(LibcameraControls, AutoSettingsOnlyEnableTheAlgorithms) {
  const auto p = planLibcameraControls(CaptureSettings{});
  EXPECT_EQ(p.aeEnable, true);
  EXPECT_EQ(p.awbEnable, true);
  EXPECT_FALSE(p.exposureTimeUs);
  EXPECT_FALSE(p.analogueGain);
  EXPECT_FALSE(p.redGain);
  EXPECT_FALSE(p.afMode);
}

TEST(LibcameraControls, UvcPipelineHasNoWhiteBalanceControl) {
  CaptureSettings s;
  s.autoExposure = false;
  s.autoWhiteBalance = false;
  // What libcamera 0.0.3's UVC pipeline handler exposes (uvcvideo.cpp).
  const std::vector<std::string> uvc{"Brightness", "Contrast",     "Saturation",
                                     "AeEnable",   "ExposureTime", "AnalogueGain"};
  EXPECT_EQ(missingLibcameraControls(planLibcameraControls(s), uvc),
            (std::vector<std::string>{"AwbEnable", "ColourGains"}));
}

TEST(LibcameraSize, NearestSizeRules) {
  const std::vector<cv::Size> sizes{{4056, 3040}, {2028, 1520}, {1332, 990}};
  EXPECT_EQ(chooseLibcameraSize(sizes, {0, 0}), cv::Size(4056, 3040));
  EXPECT_EQ(chooseLibcameraSize(sizes, {2028, 1520}), cv::Size(2028, 1520));
  EXPECT_EQ(chooseLibcameraSize(sizes, {1920, 1080}), cv::Size(2028, 1520));
  EXPECT_EQ(chooseLibcameraSize(sizes, {8000, 6000}), cv::Size(4056, 3040));
  EXPECT_FALSE(chooseLibcameraSize({}, {640, 480}));
}

cv::Mat pattern(int w, int h) {
  cv::Mat img(h, w, CV_8UC3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      img.at<cv::Vec3b>(y, x) = cv::Vec3b(static_cast<uchar>(20 + 3 * y), static_cast<uchar>(90),
                                          static_cast<uchar>(8 * x));
    }
  }
  return img;
}

std::vector<PlaneView> planesOf(const std::vector<std::uint8_t>& bytes) {
  return {PlaneView{std::span<const std::uint8_t>(bytes.data(), bytes.size())}};
}

std::vector<std::uint8_t> withStride(const cv::Mat& m, std::size_t stride) {
  const std::size_t row = m.cols * m.elemSize();
  std::vector<std::uint8_t> out(stride * m.rows, 0xEE);
  for (int y = 0; y < m.rows; ++y) {
    std::memcpy(out.data() + y * stride, m.ptr(y), row);
  }
  return out;
}

TEST(LibcameraConvert, Rgb888IsOpenCvBgrAndStrideIsHonoured) {
  const cv::Mat img = pattern(30, 20);
  const auto bytes = withStride(img, 96);  // 90 bytes of pixels + padding
  const cv::Mat out = libcameraFrameToBgr("RGB888", {30, 20}, 96, planesOf(bytes));
  ASSERT_EQ(out.size(), img.size());
  EXPECT_EQ(cv::norm(out, img, cv::NORM_INF), 0.0);
  // The result owns its pixels.
  EXPECT_NE(static_cast<const void*>(out.data), static_cast<const void*>(bytes.data()));
}

TEST(LibcameraConvert, Bgr888AndFourByteFormatsAreSwappedOrStripped) {
  const cv::Mat img = pattern(16, 8);
  cv::Mat rgb;
  cv::cvtColor(img, rgb, cv::COLOR_BGR2RGB);
  EXPECT_EQ(cv::norm(libcameraFrameToBgr("BGR888", {16, 8}, 48, planesOf(withStride(rgb, 48))), img,
                     cv::NORM_INF),
            0.0);
  cv::Mat bgra;
  cv::cvtColor(img, bgra, cv::COLOR_BGR2BGRA);
  EXPECT_EQ(cv::norm(libcameraFrameToBgr("XRGB8888", {16, 8}, 64, planesOf(withStride(bgra, 64))),
                     img, cv::NORM_INF),
            0.0);
  cv::Mat rgba;
  cv::cvtColor(img, rgba, cv::COLOR_BGR2RGBA);
  EXPECT_EQ(cv::norm(libcameraFrameToBgr("XBGR8888", {16, 8}, 64, planesOf(withStride(rgba, 64))),
                     img, cv::NORM_INF),
            0.0);
}

double meanAbsDiff(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat d;
  cv::absdiff(a, b, d);
  const auto m = cv::mean(d);
  return (m[0] + m[1] + m[2]) / 3.0;
}

TEST(LibcameraConvert, Nv12AndYuv420InOneOrSeveralPlanes) {
  const cv::Mat img = pattern(32, 16);
  cv::Mat i420;
  cv::cvtColor(img, i420, cv::COLOR_BGR2YUV_I420);  // 24 rows of 32: Y, then U, then V
  std::vector<std::uint8_t> packed(i420.datastart, i420.dataend);
  const cv::Mat fromI420 = libcameraFrameToBgr("YUV420", {32, 16}, 32, planesOf(packed));
  ASSERT_EQ(fromI420.size(), img.size());
  EXPECT_LT(meanAbsDiff(fromI420, img), 4.0);

  // NV12: interleave U and V; deliver Y and UV as two planes.
  std::vector<std::uint8_t> y(packed.begin(), packed.begin() + 32 * 16);
  std::vector<std::uint8_t> uv;
  const std::uint8_t* u = packed.data() + 32 * 16;
  const std::uint8_t* v = u + 16 * 8;
  for (int i = 0; i < 16 * 8; ++i) {
    uv.push_back(u[i]);
    uv.push_back(v[i]);
  }
  std::vector<PlaneView> two{{std::span<const std::uint8_t>(y)},
                             {std::span<const std::uint8_t>(uv)}};
  const cv::Mat fromNv12 = libcameraFrameToBgr("NV12", {32, 16}, 32, two);
  ASSERT_EQ(fromNv12.size(), img.size());
  EXPECT_LT(meanAbsDiff(fromNv12, fromI420), 1.0);
}

TEST(LibcameraConvert, YuyvAndMjpegReuseTheV4l2Decoders) {
  const cv::Mat img = pattern(32, 16);
  const auto yuyv = encodeYuyv(img);
  const cv::Mat a = libcameraFrameToBgr("YUYV", {32, 16}, 64, planesOf(yuyv));
  ASSERT_FALSE(a.empty());
  EXPECT_LT(meanAbsDiff(a, img), 6.0);
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", pattern(64, 48), jpeg);
  EXPECT_EQ(libcameraFrameToBgr("MJPEG", {64, 48}, 0, planesOf(jpeg)).size(), cv::Size(64, 48));
  jpeg.resize(jpeg.size() / 2);  // truncated: dropped, not decoded
  EXPECT_TRUE(libcameraFrameToBgr("MJPEG", {64, 48}, 0, planesOf(jpeg)).empty());
}

TEST(LibcameraConvert, UnknownFormatsAndShortPlanesGiveNothing) {
  std::vector<std::uint8_t> bytes(100, 0);
  EXPECT_TRUE(libcameraFrameToBgr("SRGGB10_CSI2P", {8, 8}, 10, planesOf(bytes)).empty());
  EXPECT_TRUE(libcameraFrameToBgr("RGB888", {30, 20}, 90, planesOf(bytes)).empty());
  EXPECT_TRUE(libcameraFrameToBgr("NV12", {30, 20}, 30, planesOf(bytes)).empty());
  EXPECT_TRUE(libcameraFrameToBgr("RGB888", {8, 8}, 24, {}).empty());
}

TEST(LibcameraCamera, WithoutACameraOpenSaysSoPlainly) {
  if (!listLibcameraCameras().empty()) {
    GTEST_SKIP() << "a libcamera camera is present; the no-camera path is not observable";
  }
  LibcameraCamera camera;
  try {
    camera.open();
    FAIL();
  } catch (const CameraError& e) {
    EXPECT_EQ(e.kind(), CameraErrorKind::kNotFound);
    EXPECT_NE(std::string(e.what()).find("no libcamera camera found"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(camera.isOpen());
  LibcameraCamera named("/base/soc/i2c0mux/i2c@1/imx477@1a");
  try {
    named.open();
    FAIL();
  } catch (const CameraError& e) {
    EXPECT_EQ(e.kind(), CameraErrorKind::kNotFound);
    EXPECT_NE(std::string(e.what()).find("imx477@1a"), std::string::npos) << e.what();
  }
  EXPECT_THROW(camera.captureStill(), CameraError);
}

}  // namespace
}  // namespace garmcap::capture
