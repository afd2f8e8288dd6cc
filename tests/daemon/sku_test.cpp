// SKU from the hang tag in the dressed frame: a QR code or a barcode, read by zbar. Tags are drawn
// on a green-screen frame the size of the rig's.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <opencv2/objdetect.hpp>
#include <string>

#include "garmcap/daemon/capture_processor.h"

namespace garmcap::daemon {
namespace {

cv::Mat greenFrame() {
  return cv::Mat(640, 480, CV_8UC3, cv::Scalar(40, 180, 40));
}

// A white tag with `code` (grey, 0 = black) scaled by `module` px, pasted at (x, y).
void pasteTag(cv::Mat& frame, const cv::Mat& code, int module, int x, int y) {
  cv::Mat big;
  cv::resize(code, big, {}, module, module, cv::INTER_NEAREST);
  cv::Mat tag(big.rows + 40, big.cols + 40, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::Mat bgr;
  cv::cvtColor(big, bgr, cv::COLOR_GRAY2BGR);
  bgr.copyTo(tag(cv::Rect(20, 20, big.cols, big.rows)));
  tag.copyTo(frame(cv::Rect(x, y, tag.cols, tag.rows)));
}

cv::Mat qr(const std::string& text) {
  auto encoder = cv::QRCodeEncoder::create();
  cv::Mat code;
  encoder->encode(text, code);
  return code;
}

// EAN-13 bars (1 px per module, 60 px high, quiet zones included) for 12 digits; the check digit
// is computed unless `check` is given.
cv::Mat ean13(const std::string& twelve, int check = -1) {
  static const char* kL[] = {"0001101", "0011001", "0010011", "0111101", "0100011",
                             "0110001", "0101111", "0111011", "0110111", "0001011"};
  static const char* kParity[] = {"LLLLLL", "LLGLGG", "LLGGLG", "LLGGGL", "LGLLGG",
                                  "LGGLLG", "LGGGLL", "LGLGLG", "LGLGGL", "LGGLGL"};
  auto digit = [&](std::size_t i) { return twelve[i] - '0'; };
  if (check < 0) {
    int sum = 0;
    for (std::size_t i = 0; i < 12; ++i)
      sum += digit(i) * (i % 2 ? 3 : 1);
    check = (10 - sum % 10) % 10;
  }
  const std::string all = twelve + std::to_string(check);
  auto invert = [](std::string s) {
    for (char& c : s)
      c = c == '0' ? '1' : '0';
    return s;
  };
  std::string bits = std::string(11, '0') + "101";
  for (std::size_t i = 1; i <= 6; ++i) {
    const std::string l = kL[all[i] - '0'];
    // G = reversed R, R = inverted L.
    std::string g = invert(l);
    std::reverse(g.begin(), g.end());
    bits += kParity[all[0] - '0'][i - 1] == 'L' ? l : g;
  }
  bits += "01010";
  for (std::size_t i = 7; i <= 12; ++i)
    bits += invert(kL[all[i] - '0']);
  bits += "101" + std::string(11, '0');
  cv::Mat code(60, static_cast<int>(bits.size()), CV_8U, cv::Scalar(255));
  for (int x = 0; x < code.cols; ++x)
    if (bits[static_cast<std::size_t>(x)] == '1')
      code.col(x).setTo(0);
  return code;
}

void requireZbarForQr() {
  if (hangTagDecoder() != "zbar")
    GTEST_SKIP() << "built without zbar (libzbar-dev): Debian's OpenCV decodes no QR codes";
}

TEST(HangTagSku, QrCodeOnTheTag) {
  requireZbarForQr();
  cv::Mat frame = greenFrame();
  pasteTag(frame, qr("SKU-2024.07_A1"), 4, 300, 60);
  EXPECT_EQ(decodeHangTagSku(frame), "SKU-2024.07_A1");
}

// A QR code printed at 8 samples per module and shrunk with area averaging to `modulePx` px per
// module at a sub-pixel offset, lens blur and sensor noise on top: what a camera sees of a tag.
cv::Mat cameraQr(const std::string& text, double modulePx, double offset, std::uint64_t seed) {
  constexpr int kOver = 8;
  cv::Mat code = qr(text), print;
  cv::resize(code, print, {}, kOver, kOver, cv::INTER_NEAREST);
  cv::Mat padded(print.rows + 4 * kOver, print.cols + 4 * kOver, CV_8UC1, cv::Scalar(255));
  print.copyTo(padded(cv::Rect(2 * kOver, 2 * kOver, print.cols, print.rows)));
  const double f = modulePx / kOver;
  const cv::Matx23d m(f, 0, offset, 0, f, offset);
  cv::Mat small;
  cv::warpAffine(padded, small, m,
                 cv::Size(cvRound(padded.cols * f) + 2, cvRound(padded.rows * f) + 2),
                 cv::INTER_AREA, cv::BORDER_CONSTANT, cv::Scalar(255));
  cv::GaussianBlur(small, small, cv::Size(0, 0), 0.7);
  cv::Mat noise(small.size(), CV_16SC1);
  cv::RNG(seed).fill(noise, cv::RNG::NORMAL, 0, 4);
  cv::Mat out;
  small.convertTo(out, CV_16SC1);
  out += noise;
  out.convertTo(out, CV_8UC1);
  return out;
}

// How small a QR code's module may get in the frame and still read, over a few sub-pixel
// placements (printed for the docs; 3 px per module is required).
TEST(HangTagSku, SmallestReadableQrModule) {
  requireZbarForQr();
  double smallest = 0;
  for (double px = 4.0; px >= 0.99; px -= 0.25) {
    int read = 0;
    for (int k = 0; k < 4; ++k) {
      const cv::Mat code =
          cameraQr("GC-24071-M", px, 0.25 * k, static_cast<std::uint64_t>(px * 100 + k));
      cv::Mat frame = greenFrame();
      cv::Mat bgr;
      cv::cvtColor(code, bgr, cv::COLOR_GRAY2BGR);
      bgr.copyTo(frame(cv::Rect(40, 40, bgr.cols, bgr.rows)));
      read += decodeHangTagSku(frame) == "GC-24071-M";
    }
    if (px >= 3.0) {
      EXPECT_EQ(read, 4) << "a QR code at " << px << " px per module";
    }
    if (read < 4)
      break;
    smallest = px;
  }
  std::printf("[qr] reads at every placement down to %.2f px per module (blur 0.7, noise 4)\n",
              smallest);
}

TEST(HangTagSku, NothingOrNotASku) {
  EXPECT_EQ(decodeHangTagSku(cv::Mat()), "");
  EXPECT_EQ(decodeHangTagSku(greenFrame()), "");
  for (int side : {1, 8, 45, 74, 200})
    EXPECT_EQ(decodeHangTagSku(cv::Mat(side, side + 16, CV_8UC3, cv::Scalar(0, 200, 0))), "");
  cv::Mat frame = greenFrame();
  pasteTag(frame, qr("https://example.invalid/?a=b c"), 4, 200, 60);
  EXPECT_EQ(decodeHangTagSku(frame), "") << "a URL is not a SKU";
}

TEST(HangTagSku, Ean13BarcodeOnTheTag) {
  requireZbarForQr();
  cv::Mat frame = greenFrame();
  pasteTag(frame, ean13("400638133393"), 3, 60, 400);
  EXPECT_EQ(decodeHangTagSku(frame), "4006381333931");
  // A wrong check digit is a misread, not a SKU.
  cv::Mat bad = greenFrame();
  pasteTag(bad, ean13("400638133393", 7), 3, 60, 400);
  EXPECT_EQ(decodeHangTagSku(bad), "");
  // A tag with both: the QR code wins (it carries the shop's own SKU).
  cv::Mat both = greenFrame();
  pasteTag(both, ean13("400638133393"), 3, 60, 400);
  pasteTag(both, qr("SHOP-77"), 4, 300, 60);
  EXPECT_EQ(decodeHangTagSku(both), "SHOP-77");
}

}  // namespace
}  // namespace garmcap::daemon
