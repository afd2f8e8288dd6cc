// SKU from a 1-D barcode on the hang tag: Code 128 (code set B) and Code 39 symbols drawn by the
// small encoders below (written from the symbology tables of ISO/IEC 15417 and 16388), printed
// on a tag in a dressed frame at a realistic scale, slightly rotated, blurred and noisy, then read
// back through decodeHangTagSku. Also what must not come back: a SKU from a frame without a tag,
// from striped fabric, from a symbol whose check character is wrong, or a different SKU from a
// damaged symbol.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <set>
#include <string>
#include <vector>

#include "garmcap/daemon/capture_processor.h"

namespace garmcap::daemon {
namespace {

// --- Code 128 ----------------------------------------------------------------------------------

// Element widths (bar, space, bar, space, bar, space) in modules of the symbol values 0..105;
// value 106 is the stop pattern (7 elements, the last bar being the termination bar).
const char* const kCode128[107] = {
    "212222", "222122", "222221", "121223", "121322", "131222", "122213", "122312", "132212",
    "221213", "221312", "231212", "112232", "122132", "122231", "113222", "123122", "123221",
    "223211", "221132", "221231", "213212", "223112", "312131", "311222", "321122", "321221",
    "312212", "322112", "322211", "212123", "212321", "232121", "111323", "131123", "131321",
    "112313", "132113", "132311", "211313", "231113", "231311", "112133", "112331", "132131",
    "113123", "113321", "133121", "313121", "211331", "231131", "213113", "213311", "213131",
    "311123", "311321", "331121", "312113", "312311", "332111", "314111", "221411", "431111",
    "111224", "111422", "121124", "121421", "141122", "141221", "112214", "112412", "122114",
    "122411", "142112", "142211", "241211", "221114", "413111", "241112", "134111", "111242",
    "121142", "121241", "114212", "124112", "124211", "411212", "421112", "421211", "212141",
    "214121", "412121", "111143", "111341", "131141", "114113", "114311", "411113", "411311",
    "113141", "114131", "311141", "411131", "211412", "211214", "211232", "2331112"};
constexpr int kStartB = 104, kStop = 106;

/// Bar/space widths of `text` (printable ASCII) in code set B: start B, the data, the modulo-103
/// check character (start value + sum of position * value) and stop. `checkOffset` spoils the
/// check character for the negative test.
std::string code128B(const std::string& text, int checkOffset = 0) {
  std::string widths = kCode128[kStartB];
  int sum = kStartB;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const int value = text[i] - 32;  // code set B: ASCII 32..127 are values 0..95
    sum += static_cast<int>(i + 1) * value;
    widths += kCode128[value];
  }
  widths += kCode128[(sum + checkOffset) % 103];
  widths += kCode128[kStop];
  return widths;
}

// --- Code 39 -----------------------------------------------------------------------------------

// Each character: 9 elements (bar, space, ..., bar), 'w' wide and 'n' narrow; three are wide.
const std::map<char, std::string> kCode39 = {
    {'0', "nnnwwnwnn"}, {'1', "wnnwnnnnw"}, {'2', "nnwwnnnnw"}, {'3', "wnwwnnnnn"},
    {'4', "nnnwwnnnw"}, {'5', "wnnwwnnnn"}, {'6', "nnwwwnnnn"}, {'7', "nnnwnnwnw"},
    {'8', "wnnwnnwnn"}, {'9', "nnwwnnwnn"}, {'A', "wnnnnwnnw"}, {'B', "nnwnnwnnw"},
    {'C', "wnwnnwnnn"}, {'D', "nnnnwwnnw"}, {'E', "wnnnwwnnn"}, {'F', "nnwnwwnnn"},
    {'G', "nnnnnwwnw"}, {'H', "wnnnnwwnn"}, {'I', "nnwnnwwnn"}, {'J', "nnnnwwwnn"},
    {'K', "wnnnnnnww"}, {'L', "nnwnnnnww"}, {'M', "wnwnnnnwn"}, {'N', "nnnnwnnww"},
    {'O', "wnnnwnnwn"}, {'P', "nnwnwnnwn"}, {'Q', "nnnnnnwww"}, {'R', "wnnnnnwwn"},
    {'S', "nnwnnnwwn"}, {'T', "nnnnwnwwn"}, {'U', "wwnnnnnnw"}, {'V', "nwwnnnnnw"},
    {'W', "wwwnnnnnn"}, {'X', "nwnnwnnnw"}, {'Y', "wwnnwnnnn"}, {'Z', "nwwnwnnnn"},
    {'-', "nwnnnnwnw"}, {'.', "wwnnnnwnn"}, {' ', "nwwnnnwnn"}, {'$', "nwnwnwnnn"},
    {'/', "nwnwnnnwn"}, {'+', "nwnnnwnwn"}, {'%', "nnnwnwnwn"}, {'*', "nwnnwnwnn"}};

/// Bar/space widths of "*text*" with wide = 3 modules and a narrow inter-character gap.
/// `withStop` false leaves off the stop character (a torn tag).
std::string code39(const std::string& text, bool withStop = true) {
  const std::string all = "*" + text + (withStop ? "*" : "");
  std::string widths;
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (i > 0)
      widths += '1';  // inter-character gap (a space)
    for (char e : kCode39.at(all[i]))
      widths += e == 'w' ? '3' : '1';
  }
  return widths;
}

// --- printing and photographing the tag ----------------------------------------------------

/// One row of modules (1 = ink) from alternating bar/space widths starting with a bar, with
/// quiet zones of `quiet` modules.
std::vector<unsigned char> modules(const std::string& widths, int quiet) {
  std::vector<unsigned char> row(static_cast<std::size_t>(quiet), 0);
  for (std::size_t i = 0; i < widths.size(); ++i)
    row.insert(row.end(), static_cast<std::size_t>(widths[i] - '0'), i % 2 == 0 ? 1 : 0);
  row.insert(row.end(), static_cast<std::size_t>(quiet), 0);
  return row;
}

/// How the tag appears in the still.
struct Shot {
  double modulePx = 2.0;  // narrow bar width in the frame
  int barHeightPx = 90;
  double angleDeg = 2.5;    // the tag hangs slightly askew
  double blurSigma = 0.7;   // focus and motion
  double noiseSigma = 4.0;  // sensor noise, grey levels
  cv::Point at{520, 1350};  // where the tag hangs
  std::uint64_t seed = 1;
  int damageBlots = 0;  // ink spots and scuffs over part of the bars' height
  int damageBands = 0;  // smears and scratches across the whole height (every scan line)
};

/// A portrait still the size of a binned 12 MP sensor mode (1520 x 2028): green screen, a dark
/// garment, and the hang tag printed with `widths`, photographed as `shot` says.
cv::Mat photographTag(const std::string& widths, const Shot& shot) {
  cv::Mat frame(2028, 1520, CV_8UC3, cv::Scalar(40, 175, 45));
  cv::rectangle(frame, cv::Rect(380, 500, 760, 1300), cv::Scalar(70, 50, 120), cv::FILLED);
  // Print at 8 samples per module, then shrink with area averaging to the module size in the
  // frame: bar edges fall between pixels as they do in a photograph.
  const int kOver = 8;
  const auto row = modules(widths, 10);
  cv::Mat print(shot.barHeightPx * kOver / 2, static_cast<int>(row.size()) * kOver, CV_8U,
                cv::Scalar(228));  // tag paper
  for (std::size_t m = 0; m < row.size(); ++m)
    if (row[m])
      print.colRange(static_cast<int>(m) * kOver, static_cast<int>(m + 1) * kOver).setTo(35);
  cv::RNG rng(shot.seed);
  for (int i = 0; i < shot.damageBlots; ++i) {
    const cv::Point c(rng.uniform(0, print.cols), rng.uniform(0, print.rows));
    const int r = rng.uniform(kOver, 4 * kOver);
    cv::circle(print, c, r, cv::Scalar(rng.uniform(0, 2) ? 35 : 228), cv::FILLED);
  }
  for (int i = 0; i < shot.damageBands; ++i) {
    const int w = rng.uniform(kOver / 2, 3 * kOver);
    const int x = rng.uniform(10 * kOver, print.cols - 10 * kOver - w);  // inside the symbol
    print.colRange(x, x + w).setTo(rng.uniform(0, 2) ? 35 : 228);
  }
  const double scale = shot.modulePx / kOver;
  cv::Mat bars;
  cv::resize(print, bars, cv::Size(cvRound(print.cols * scale), cvRound(print.rows * scale * 2)), 0,
             0, cv::INTER_AREA);
  // The tag: a paper margin around the bars, rotated, pasted where paper covers the garment.
  cv::Mat tag(bars.rows + 60, bars.cols + 30, CV_8U, cv::Scalar(228));
  bars.copyTo(tag(cv::Rect(15, 20, bars.cols, bars.rows)));
  cv::Mat mask(tag.size(), CV_8U, cv::Scalar(255));
  const cv::Point2f centre(tag.cols / 2.0f, tag.rows / 2.0f);
  cv::Mat rot = cv::getRotationMatrix2D(centre, shot.angleDeg, 1.0);
  const cv::Rect2f box =
      cv::RotatedRect(centre, tag.size(), static_cast<float>(shot.angleDeg)).boundingRect2f();
  rot.at<double>(0, 2) += box.width / 2.0 - centre.x;
  rot.at<double>(1, 2) += box.height / 2.0 - centre.y;
  const cv::Size out(cvCeil(box.width), cvCeil(box.height));
  cv::Mat tagRot, maskRot;
  cv::warpAffine(tag, tagRot, rot, out, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(228));
  cv::warpAffine(mask, maskRot, rot, out, cv::INTER_NEAREST, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::Mat tagBgr;
  cv::cvtColor(tagRot, tagBgr, cv::COLOR_GRAY2BGR);
  tagBgr.copyTo(frame(cv::Rect(shot.at, out)), maskRot);
  // The lens and the sensor.
  cv::GaussianBlur(frame, frame, cv::Size(0, 0), shot.blurSigma);
  cv::Mat noise(frame.size(), CV_16SC3);
  rng.fill(noise, cv::RNG::NORMAL, 0, shot.noiseSigma);
  cv::Mat noisy;
  frame.convertTo(noisy, CV_16SC3);
  noisy += noise;
  noisy.convertTo(frame, CV_8UC3);  // saturates
  return frame;
}

void requireZbar() {
  if (hangTagDecoder() != "zbar")
    GTEST_SKIP() << "built without zbar (libzbar-dev): no 1-D barcodes are read";
}

// --- the encoders against the published tables' own rules -------------------------------------

TEST(Barcode1D, EncoderTablesKeepTheirSymbologyRules) {
  // Code 128: every symbol is 11 modules in 3 bars and 3 spaces, each 1..4 modules, with an even
  // number of bar modules; the stop is 13 modules; all patterns differ.
  std::set<std::string> seen;
  for (int v = 0; v < 107; ++v) {
    const std::string p = kCode128[v];
    ASSERT_EQ(p.size(), v == kStop ? 7u : 6u) << v;
    int total = 0, bars = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      ASSERT_TRUE(p[i] >= '1' && p[i] <= '4') << v;
      total += p[i] - '0';
      if (i % 2 == 0)
        bars += p[i] - '0';
    }
    EXPECT_EQ(total, v == kStop ? 13 : 11) << v;
    EXPECT_EQ(bars % 2, 0) << v;
    EXPECT_TRUE(seen.insert(p).second) << "duplicate pattern at " << v;
  }
  // A worked check character: "PJJ123C" in set B = (104 + 1*48 + 2*42 + 3*42 + 4*17 + 5*18 +
  // 6*19 + 7*35) mod 103 = 879 mod 103 = 55.
  const std::string w = code128B("PJJ123C");
  EXPECT_EQ(w.substr(w.size() - 13, 6), kCode128[55]);
  // Code 39: 3 of 9 elements wide: two bars and one space, or (for $ / + %) three spaces.
  seen.clear();
  for (const auto& [c, p] : kCode39) {
    ASSERT_EQ(p.size(), 9u) << c;
    int wideBars = 0, wideSpaces = 0;
    for (std::size_t i = 0; i < 9; ++i)
      (i % 2 == 0 ? wideBars : wideSpaces) += p[i] == 'w';
    const bool special = std::string("$/+%").find(c) != std::string::npos;
    EXPECT_EQ(wideBars, special ? 0 : 2) << c;
    EXPECT_EQ(wideSpaces, special ? 3 : 1) << c;
    EXPECT_TRUE(seen.insert(p).second) << "duplicate pattern for " << c;
  }
  EXPECT_EQ(kCode39.size(), 44u);
}

// --- reading them off the tag ----------------------------------------------------------------

TEST(HangTagSku, Code128OnTheTag) {
  requireZbar();
  for (const std::string sku : {"GC-24071-M", "sku_2024.07b", "A1"}) {
    for (double modulePx : {2.0, 2.6}) {
      Shot shot;
      shot.modulePx = modulePx;
      shot.seed = sku.size() * 31 + static_cast<std::uint64_t>(modulePx * 10);
      EXPECT_EQ(decodeHangTagSku(photographTag(code128B(sku), shot)), sku)
          << sku << " at " << modulePx << " px per module";
    }
  }
}

TEST(HangTagSku, Code39OnTheTag) {
  requireZbar();
  for (const std::string sku : {"GC-24071.M", "A1B2C3", "7"}) {
    for (double modulePx : {2.0, 2.4}) {
      Shot shot;
      shot.modulePx = modulePx;
      shot.angleDeg = -3;
      shot.seed = sku.size() * 17 + static_cast<std::uint64_t>(modulePx * 10);
      EXPECT_EQ(decodeHangTagSku(photographTag(code39(sku), shot)), sku)
          << sku << " at " << modulePx << " px per module";
    }
  }
}

// How small a printed module may get in the frame and still read (printed for the docs; only
// the 2 px case is a requirement, above).
TEST(HangTagSku, SmallestReadableModule) {
  requireZbar();
  for (const auto& [name, widths] : std::vector<std::pair<std::string, std::string>>{
           {"Code 128", code128B("GC-24071-M")}, {"Code 39", code39("GC-24071.M")}}) {
    double smallest = 0;
    for (double px = 2.4; px >= 0.99; px -= 0.2) {
      Shot shot;
      shot.modulePx = px;
      if (decodeHangTagSku(photographTag(widths, shot)) !=
          (name == "Code 128" ? "GC-24071-M" : "GC-24071.M"))
        break;
      smallest = px;
    }
    std::printf("[barcode] %s reads down to %.1f px per module (blur %.1f, noise %.0f)\n",
                name.c_str(), smallest, Shot{}.blurSigma, Shot{}.noiseSigma);
    EXPECT_GT(smallest, 0) << name;
    EXPECT_LE(smallest, 2.0) << name;
  }
}

// --- what must not become a SKU ----------------------------------------------------------------

TEST(HangTagSku, NoTagNoSku) {
  Shot shot;
  cv::Mat frame = photographTag("", shot);  // a blank tag: paper only
  EXPECT_EQ(decodeHangTagSku(frame), "");
  // Striped fabric: regular bars of several pitches over the whole garment.
  cv::Mat stripes(2028, 1520, CV_8UC3, cv::Scalar(40, 175, 45));
  for (int pitch : {4, 6, 9, 14}) {
    for (int x = 380 + (pitch - 4) * 40; x < 1140; x += pitch)
      cv::rectangle(stripes, cv::Rect(x, 500 + (pitch - 4) * 100, pitch / 2, 300),
                    cv::Scalar(30, 30, 30), cv::FILLED);
  }
  cv::GaussianBlur(stripes, stripes, cv::Size(0, 0), 0.7);
  EXPECT_EQ(decodeHangTagSku(stripes), "");
}

TEST(HangTagSku, Code128WithAWrongCheckCharacterIsNoSku) {
  requireZbar();
  for (int offset : {1, 7, 50}) {
    Shot shot;
    shot.seed = static_cast<std::uint64_t>(offset);
    EXPECT_EQ(decodeHangTagSku(photographTag(code128B("GC-24071-M", offset), shot)), "")
        << "check character off by " << offset;
  }
}

TEST(HangTagSku, TornCode39WithoutItsStopIsNoSku) {
  requireZbar();
  Shot shot;
  EXPECT_EQ(decodeHangTagSku(photographTag(code39("GC-24071.M", false), shot)), "");
}

// Ink spots, smears and scratches over the bars: the tag may become unreadable, but what is read
// is the printed SKU and never another one. Odd seeds spot part of the bars' height (zbar reads
// on the lines the spots miss); even seeds draw bands across the whole height, which change bar
// and space widths on every scan line.
TEST(HangTagSku, DamagedBarcodesGiveTheirSkuOrNone) {
  requireZbar();
  const std::vector<std::pair<std::string, std::string>> symbols = {
      {"GC-24071-M", code128B("GC-24071-M")}, {"GC-24071.M", code39("GC-24071.M")}};
  for (const auto& [sku, widths] : symbols) {
    int read = 0, none = 0, wrong = 0;
    for (std::uint64_t seed = 1; seed <= 16; ++seed) {
      Shot shot;
      shot.seed = seed;
      if (seed % 2)
        shot.damageBlots = 2 + static_cast<int>(seed % 5);
      else
        shot.damageBands = 1 + static_cast<int>(seed % 3);
      shot.modulePx = seed % 4 < 2 ? 2.0 : 2.4;
      const std::string got = decodeHangTagSku(photographTag(widths, shot));
      if (got.empty()) {
        ++none;
      } else if (got == sku) {
        ++read;
      } else {
        ++wrong;
        ADD_FAILURE() << "damaged " << sku << " (seed " << seed << ") read as '" << got << "'";
      }
    }
    std::printf("[barcode] damaged %s: %d read, %d unreadable, %d wrong\n", sku.c_str(), read, none,
                wrong);
    // Otherwise the damage was too mild to test anything.
    EXPECT_GE(none, 1) << sku;
  }
}

}  // namespace
}  // namespace garmcap::daemon
