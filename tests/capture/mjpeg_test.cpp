// MJPEG framing checks and YUYV/MJPEG decoding (the pure part of the V4L2 back end).

#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "garmcap/capture/v4l2_decode.h"

namespace garmcap::capture {
namespace {

cv::Mat testImage(int w, int h) {
  cv::Mat img(h, w, CV_8UC3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      img.at<cv::Vec3b>(y, x) =
          cv::Vec3b(static_cast<uchar>(30 + y % 50), static_cast<uchar>(100 + (x + y) % 60),
                    static_cast<uchar>(255 * x / (w - 1)));
    }
  }
  return img;
}

std::vector<std::uint8_t> jpeg(const cv::Mat& img) {
  std::vector<std::uint8_t> out;
  cv::imencode(".jpg", img, out, {cv::IMWRITE_JPEG_QUALITY, 95});
  return out;
}

TEST(MjpegCheck, AcceptsAWellFramedJpeg) {
  EXPECT_EQ(checkMjpegFrame(jpeg(testImage(64, 48))), MjpegCheck::kOk);
}

TEST(MjpegCheck, AcceptsZeroPaddingAfterEndMarker) {
  auto bytes = jpeg(testImage(64, 48));
  bytes.insert(bytes.end(), 37, 0x00);  // UVC drivers pad payloads
  EXPECT_EQ(checkMjpegFrame(bytes), MjpegCheck::kOk);
  EXPECT_FALSE(decodeMjpeg(bytes).empty());
}

TEST(MjpegCheck, RejectsMissingStartMarker) {
  auto bytes = jpeg(testImage(64, 48));
  bytes[1] = 0x00;
  EXPECT_EQ(checkMjpegFrame(bytes), MjpegCheck::kNoStartMarker);
}

TEST(MjpegCheck, RejectsTruncatedFrame) {
  auto bytes = jpeg(testImage(64, 48));
  bytes.resize(bytes.size() * 2 / 3);
  EXPECT_EQ(checkMjpegFrame(bytes), MjpegCheck::kBadEndMarker);
}

TEST(MjpegCheck, RejectsGarbageAfterEndMarker) {
  auto bytes = jpeg(testImage(64, 48));
  bytes.push_back(0x12);
  bytes.push_back(0x34);
  EXPECT_EQ(checkMjpegFrame(bytes), MjpegCheck::kBadEndMarker);
}

TEST(MjpegCheck, RejectsTinyFrames) {
  std::vector<std::uint8_t> stub{0xFF, 0xD8, 0xFF, 0xD9};
  EXPECT_EQ(checkMjpegFrame(stub), MjpegCheck::kTooSmall);
  EXPECT_EQ(checkMjpegFrame({}), MjpegCheck::kTooSmall);
  std::vector<std::uint8_t> small(kMinMjpegBytes - 1, 0x00);
  small[0] = 0xFF;
  small[1] = 0xD8;
  small[small.size() - 2] = 0xFF;
  small[small.size() - 1] = 0xD9;
  EXPECT_EQ(checkMjpegFrame(small), MjpegCheck::kTooSmall);
}

TEST(MjpegDecode, DecodesToBgrOfTheRightSize) {
  const cv::Mat img = testImage(96, 64);
  const cv::Mat out = decodeMjpeg(jpeg(img));
  ASSERT_EQ(out.size(), img.size());
  ASSERT_EQ(out.type(), CV_8UC3);
  EXPECT_LT(cv::norm(out, img, cv::NORM_L1) / static_cast<double>(img.total() * 3), 3.0);
}

TEST(MjpegDecode, GarbageGivesEmptyNotAnException) {
  std::vector<std::uint8_t> garbage(500, 0xAB);
  garbage[0] = 0xFF;
  garbage[1] = 0xD8;
  EXPECT_TRUE(decodeMjpeg(garbage).empty());
  EXPECT_TRUE(decodeMjpeg({}).empty());
}

TEST(YuyvDecode, RoundTripKeepsColoursWithinQuantisation) {
  const cv::Mat img = testImage(64, 32);
  const auto yuyv = encodeYuyv(img);
  ASSERT_EQ(yuyv.size(), 64u * 32u * 2u);
  const cv::Mat out = decodeYuyv(yuyv, 64, 32, 128);
  ASSERT_EQ(out.size(), img.size());
  // 4:2:2 chroma subsampling and limited range: small errors, none systematic.
  cv::Mat diff;
  cv::absdiff(out, img, diff);
  EXPECT_LT(cv::mean(diff)[0] + cv::mean(diff)[1] + cv::mean(diff)[2], 3 * 6.0);
  // Red grows to the right, as in the source (no channel swap).
  EXPECT_GT(out.at<cv::Vec3b>(10, 60)[2], out.at<cv::Vec3b>(10, 2)[2] + 150);
}

TEST(YuyvDecode, HonoursBytesPerLinePadding) {
  const cv::Mat img = testImage(32, 8);
  const auto tight = encodeYuyv(img);
  const int stride = 32 * 2 + 16;
  std::vector<std::uint8_t> padded(static_cast<std::size_t>(stride) * 8, 0x80);
  for (int y = 0; y < 8; ++y) {
    std::copy_n(tight.begin() + y * 64, 64, padded.begin() + y * stride);
  }
  const cv::Mat a = decodeYuyv(tight, 32, 8, 64);
  const cv::Mat b = decodeYuyv(padded, 32, 8, stride);
  ASSERT_FALSE(b.empty());
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
}

TEST(YuyvDecode, RefusesShortBuffersAndOddWidths) {
  std::vector<std::uint8_t> bytes(100, 0x80);
  EXPECT_TRUE(decodeYuyv(bytes, 32, 8, 64).empty());
  EXPECT_TRUE(decodeYuyv(bytes, 5, 2, 10).empty());
  EXPECT_TRUE(decodeYuyv(bytes, 8, 2, 4).empty());  // stride below 2 * width
}

TEST(Fourcc, PrintsAsText) {
  EXPECT_EQ(fourccToString(V4L2_PIX_FMT_MJPEG), "MJPG");
  EXPECT_EQ(fourccToString(V4L2_PIX_FMT_YUYV), "YUYV");
}

}  // namespace
}  // namespace garmcap::capture
