#include "stage_masks.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <utility>

#include "frame_ops.h"
#include "garmcap/pipeline/capture_pipeline.h"

namespace garmcap::pipeline {
namespace {

// Dressed foreground this far from the exposed form is garment without asking GrabCut.
constexpr double kSettledCm = 2.0;
// Exposed form whose difference is below this fraction of the noise thresholds is sure form from
// this far from any garment evidence (a garment the colour of the form reads near the threshold,
// and keeps the wider margin above for GrabCut to find it).
constexpr double kClearlyExposed = 0.5;
constexpr double kClearlySettledCm = 0.5;
// The colour-difference noise floor is read on the form from this far above its side neck up.
constexpr double kNoiseAboveNeckCm = 4.0;
constexpr double kAveragedDifferenceCm = 0.5;

// The garment's shadow on the form (shadowOnForm): at least this much darker in Lab lightness
// (0-255), with its a,b within a constant plus a share of the form's own chroma (as dimmed) of
// the form's colour dimmed to that lightness.
constexpr float kShadowMinDarkening = 8.0f;
constexpr float kShadowChroma = 4.0f;
constexpr float kShadowChromaShare = 0.1f;
// Over a dark garment, only a shallow shade (L* + 16 at least this share of the bare form's) may
// also be tinted by the light the garment bounces into it, its chroma changed by up to this
// fraction of the darkening plus kShadowChroma; elsewhere any shade may.
constexpr float kShadowShallow = 0.5f;
constexpr float kShadowChromaPerLightness = 0.2f;
// A shadow fades into the exposed form through its penumbra, darker by less than
// kShadowMinDarkening but with the form's chroma kept, over at most this far.
constexpr double kShadowPenumbraCm = 1.0;
constexpr double kShadowBlurCm = 0.2;
// A shadow band is at least this wide (thinner is a garment's stripe or print, shaded).
constexpr double kShadowMinWidthCm = 0.8;
// More of the changed form than this looking like shadow is a dark neutral garment.
constexpr double kShadowMaxShareOfChange = 0.4;
// closedAcrossForm: garment over the screen within this far beyond the bare form's edge (at
// least this much of it), not counting the first kClosureClearCm (the two keys' edges differ).
constexpr double kClosureReachCm = 1.5;
constexpr double kClosureMinCm = 0.3;
constexpr double kClosureClearCm = 0.3;
// closedAcrossForm: rows between closed rows of the same section, over at most this far, are
// never sure background. A garment that hugs the form stands off it by about kClosureClearCm +
// kClosureMinCm, so its rows pass and fail the test by a pixel (torso rig case_014: a
// form-coloured skirt just under the waist, 4 open rows between closed ones made sure background
// as exposed form far from garment evidence, and GrabCut had to cut across: skirt length 54 cm
// short). A tube closed above and below does not leave the form for less than a centimetre and
// come back, but those rows are left to GrabCut rather than made garment: near a hem that rises
// at the centre front the sides pass while the form shows between them, and any more sure or
// probable garment moved GrabCut's colour models (physical case_023: a lobe of the form below a
// white top's hem, 1.2 cm on its length; a strip of arm in its cut-out).
constexpr double kClosureGapCm = 1.0;
// closedAcrossForm's values: a closed row's pixels, and those of rows between closed rows.
constexpr uchar kClosedRow = 255, kBetweenClosedRows = 128;
// coveredFromShoulders: the bust's closure is looked for this far below the bust.
constexpr double kShoulderBustBandCm = 1.0;

// The Lab difference of the two frames averaged over about sigmaPx before taking its size
// (a,b magnitude plus half of L, as the fine difference): sensor noise averages out, while a
// garment the colour of the form keeps its small, steady offset and its folds. Each channel is
// clipped at `clip` first, so that a strong garment edge spreads only a thin halo. Only pixels of
// `over` (the form) are averaged: the garment's shadow changes the screen beside the form, and
// that change must not reach the form's own edge pixels.
cv::Mat1f averagedDifference(const cv::Mat& labE, const cv::Mat& labD, const cv::Mat& over,
                             double sigmaPx, float clip) {
  // One pass for the weighted, clipped signed difference (at 2 MP the chain of whole-image
  // operations cost ~100 ms more).
  cv::Mat3f weighted(labE.size());
  cv::Mat1f weight(labE.size());
  cv::parallel_for_(cv::Range(0, labE.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const cv::Vec3b* e = labE.ptr<cv::Vec3b>(y);
      const cv::Vec3b* d = labD.ptr<cv::Vec3b>(y);
      const uchar* o = over.ptr(y);
      cv::Vec3f* wd = weighted.ptr<cv::Vec3f>(y);
      float* w = weight.ptr<float>(y);
      for (int x = 0; x < labE.cols; ++x) {
        w[x] = static_cast<float>(o[x]) * (1.0f / 255.0f);
        for (int k = 0; k < 3; ++k)
          wd[x][k] = std::clamp(static_cast<float>(d[x][k]) - e[x][k], -clip, clip) * w[x];
      }
    }
  });
  cv::Mat small, smallW;
  cv::resize(weighted, small, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
  cv::resize(weight, smallW, small.size(), 0, 0, cv::INTER_AREA);
  const double sigma = std::max(1.0, sigmaPx / 2);
  cv::GaussianBlur(small, small, cv::Size(), sigma);
  cv::GaussianBlur(smallW, smallW, cv::Size(), sigma);
  smallW = cv::max(smallW, 1e-3f);
  cv::Mat ch[3];
  cv::split(small, ch);
  for (cv::Mat& c : ch)
    cv::divide(c, smallW, c);
  cv::Mat1f size;
  cv::magnitude(ch[1], ch[2], size);
  size += 0.5f * cv::abs(ch[0]);
  cv::Mat1f out;
  cv::resize(size, out, labE.size(), 0, 0, cv::INTER_LINEAR);
  return out;
}

// Per-pixel size of the Lab difference (a,b magnitude plus half of L). On `tolerant` pixels (the
// form's outline) it is the smallest over the bare frame's 3x3 neighbourhood: an edge that only
// moved by a sub-pixel camera shake is unchanged, a garment over it is not.
cv::Mat1f labDifference(const cv::Mat& labE, const cv::Mat& labD, const cv::Mat& tolerant) {
  auto size = [](const cv::Vec3b& e, const cv::Vec3b& d) {
    const float l = std::abs(static_cast<float>(e[0]) - d[0]);
    const float a = static_cast<float>(e[1]) - d[1], b = static_cast<float>(e[2]) - d[2];
    return std::sqrt(a * a + b * b) + 0.5f * l;
  };
  cv::Mat1f out(labE.size());
  cv::parallel_for_(cv::Range(0, labE.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const cv::Vec3b* e = labE.ptr<cv::Vec3b>(y);
      const cv::Vec3b* d = labD.ptr<cv::Vec3b>(y);
      const uchar* t = tolerant.ptr(y);
      float* o = out.ptr<float>(y);
      const bool inner = y > 0 && y + 1 < labE.rows;
      for (int x = 0; x < labE.cols; ++x) {
        o[x] = size(e[x], d[x]);
        if (!t[x] || !inner || x == 0 || x + 1 == labE.cols)
          continue;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            o[x] = std::min(o[x], size(labE.at<cv::Vec3b>(y + dy, x + dx), d[x]));
      }
    }
  });
  return out;
}

// Form pixels that look like the bare form in shadow: darker in the dressed frame by at least
// `minDarkening`, with the form's own chroma dimmed with it. Dimming a colour by a factor scales
// a*, b* and L* + 16 by the same factor (Lab's cube root), so the shade of the form has its hue
// and a chroma scaled by (L*d + 16) / (L*e + 16); the despilled frames leave no green bounce
// from the screen in the shade. The garment throws its shadow on the form below its hem (a band
// on the thighs under a top, on the shins under a skirt, in the gap between the legs) and that
// band is no garment; a garment over the form changes its colour otherwise, and a dark one keeps
// little of the form's chroma: a near-black skirt over a beige form is neutral where the form's
// shade would still be beige (physical rig, 2 MP: the test that allowed any chroma change up to
// a fifth of the darkening took a dark skirt for shadow, was switched off by
// kShadowMaxShareOfChange, and the thighs in its shade were typed as pants' legs). A shade
// with L* + 16 at least `shallowFrom` of the bare form's is also lit by what the garment bounces
// into it and may take on some of its colour (the thighs under a light yellow top): there the
// chroma may change by a fifth of the darkening plus kShadowChroma (shallowFrom 0: everywhere,
// as this test read before). Over a neutral form a near-black garment and the form's deep shade
// cannot be told apart; `shallowOnly` then keeps only shade with L* + 16 at least `shallowFrom` of
// the bare form's, dimmed or tinted: a near-black skirt dims the ivory form to 0.3-0.45, the
// shade it throws on the thighs to 0.53-0.92 (fresh physical rig, seed 9494 case 5).
// Both Lab frames are averaged over about 0.2 cm first (sensor noise), once for every test
// (ShadowFrames).
struct ShadowFrames {
  cv::Mat e, d;  // bare and dressed Lab, blurred
};

ShadowFrames shadowFrames(const cv::Mat& labE, const cv::Mat& labD, double pxPerCm) {
  const double sigma = std::max(0.8, kShadowBlurCm * pxPerCm);
  ShadowFrames f;
  cv::GaussianBlur(labE, f.e, cv::Size(), sigma);
  cv::GaussianBlur(labD, f.d, cv::Size(), sigma);
  return f;
}

cv::Mat shadowOnForm(const ShadowFrames& frames, const cv::Mat& form, float minDarkening,
                     float shallowFrom, bool shallowOnly = false) {
  const cv::Mat& e = frames.e;
  const cv::Mat& d = frames.d;
  cv::Mat out(e.size(), CV_8UC1, cv::Scalar(0));
  // 8-bit Lab: L = L* x 255/100, a = a* + 128, b = b* + 128.
  constexpr float kL16 = 16.0f * 255.0f / 100.0f;
  cv::parallel_for_(cv::Range(0, e.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const cv::Vec3b* pe = e.ptr<cv::Vec3b>(y);
      const cv::Vec3b* pd = d.ptr<cv::Vec3b>(y);
      const uchar* f = form.ptr(y);
      uchar* o = out.ptr(y);
      for (int x = 0; x < e.cols; ++x) {
        if (!f[x])
          continue;
        const float dl = static_cast<float>(pd[x][0]) - pe[x][0];
        if (dl > -minDarkening)
          continue;
        const float k = (pd[x][0] + kL16) / (pe[x][0] + kL16);
        if (shallowOnly && k < shallowFrom)
          continue;
        const float ae = k * (static_cast<float>(pe[x][1]) - 128.0f);
        const float be = k * (static_cast<float>(pe[x][2]) - 128.0f);
        const float da = static_cast<float>(pd[x][1]) - 128.0f - ae;
        const float db = static_cast<float>(pd[x][2]) - 128.0f - be;
        const float tolerance = kShadowChroma + kShadowChromaShare * std::sqrt(ae * ae + be * be);
        const float dab = std::hypot(static_cast<float>(pd[x][1]) - pe[x][1],
                                     static_cast<float>(pd[x][2]) - pe[x][2]);
        const bool dimmed = da * da + db * db <= tolerance * tolerance;
        const bool tinted =
            k >= shallowFrom && dab <= kShadowChromaPerLightness * -dl + kShadowChroma;
        o[x] = dimmed || tinted ? 255 : 0;
      }
    }
  });
  return out;
}

// Form pixels a garment must cover because it hangs beyond both edges of the form there: per row
// of the work frame from the bust down, for the torso's section and (below the crotch) each
// leg's, when the dressed foreground shows garment over the screen just outside both edges of
// the section (within kClosureReachCm, beyond kClosureClearCm of the bare form), the garment is a
// tube round that part of the form and covers its front between them. A garment the colour of
// the form matches the bare frame within the noise over large patches there, which the exposed
// test then takes for bare form (physical rig: form-coloured dresses lost their skirts). Closed
// rows' pixels are kClosedRow, those of rows between closed rows kBetweenClosedRows.
cv::Mat closedAcrossForm(const cv::Mat& fgD, const cv::Mat& formMask, const FormView& view,
                         double ws, double sw) {
  cv::Mat out = cv::Mat::zeros(fgD.size(), CV_8UC1);
  cv::Mat formGrown;
  const int clear = std::max(1, static_cast<int>(std::lround(kClosureClearCm * sw)));
  cv::dilate(formMask, formGrown,
             cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * clear + 1, 2 * clear + 1)));
  const cv::Mat outside = fgD & ~formGrown;
  const int reach = static_cast<int>(std::lround(kClosureReachCm * sw));
  const int minPx = std::max(2, static_cast<int>(std::lround(kClosureMinCm * sw)));
  const int fromRow = std::max(0, static_cast<int>(view.rowOfHeight(view.bustCm()) * ws));
  auto garmentBeside = [&](int row, int from, int to) {
    from = std::clamp(from, 0, outside.cols - 1);
    to = std::clamp(to, 0, outside.cols - 1);
    return from <= to && cv::countNonZero(outside.row(row).colRange(from, to + 1)) >= minPx;
  };
  auto fill = [&](int row, const calib::RowSection& sec, uchar value) {
    const int l = static_cast<int>(std::lround(sec.leftPx * ws));
    const int r = static_cast<int>(std::lround(sec.rightPx * ws));
    if (r > l && l >= 0 && r < out.cols)
      out.row(row).colRange(l, r + 1).setTo(value, fgD.row(row).colRange(l, r + 1));
  };
  auto closes = [&](int row, const calib::RowSection& sec) {
    const int l = static_cast<int>(std::lround(sec.leftPx * ws));
    const int r = static_cast<int>(std::lround(sec.rightPx * ws));
    return r > l && l >= 0 && r < out.cols && garmentBeside(row, l - clear - reach, l - clear) &&
           garmentBeside(row, r + clear, r + clear + reach);
  };
  // Each part (torso, left leg, right leg) is followed down on its own: a leg's rows are not
  // "between" the torso's.
  enum Part { kTorso, kLeftLeg, kRightLeg, kParts };
  auto sectionAt = [&](int row, int part) -> std::optional<calib::RowSection> {
    const int full = static_cast<int>(std::lround(row / ws));
    const auto torso = view.torsoAtRow(full);
    if (part == kTorso)
      return torso;
    return torso ? std::nullopt : view.legAtRow(full, part - kLeftLeg);
  };
  const int gapPx = std::max(1, static_cast<int>(std::lround(kClosureGapCm * sw)));
  for (int part = 0; part < kParts; ++part) {
    int lastClosed = -1;
    for (int row = fromRow; row < out.rows; ++row) {
      const auto sec = sectionAt(row, part);
      if (!sec) {
        lastClosed = -1;
        continue;
      }
      if (!closes(row, *sec))
        continue;
      fill(row, *sec, kClosedRow);
      if (lastClosed >= 0 && row - lastClosed - 1 <= gapPx)
        for (int between = lastClosed + 1; between < row; ++between)
          fill(between, *sectionAt(between, part), kBetweenClosedRows);
      lastClosed = row;
    }
  }
  return out;
}

// Form pixels a garment must cover because it lies on the form's shoulders: per work column
// between the neck and the torso's edge below the armpit, where the dressed foreground shows
// garment over the screen just above the bare form's shoulder line (beyond kClosureClearCm, within
// kClosureReachCm), the garment covers that column from there down to the bust, provided
// closedAcrossForm found it a tube round the bust (`closed` holds garment on the bust's row). A
// bodice hangs from the shoulders: the cloth over the shoulder line stands off the form by its
// thickness and ease, which the screen shows (physical rig: a form-coloured dress's bodice above
// the bust matched the bare frame within the noise, and its garment length read 20.7 cm short),
// and a strap or shoulder seam runs on down the front to the bodice. A neckline does not stand in
// the way: its opening lies between the neck's columns, where the shoulder line is the neck's and
// nothing stands above it; a bare shoulder shows no garment above it.
cv::Mat coveredFromShoulders(const cv::Mat& fgD, const cv::Mat& formMask, const cv::Mat& closed,
                             const FormView& view, double ws, double sw) {
  cv::Mat out = cv::Mat::zeros(fgD.size(), CV_8UC1);
  const int bustRow = static_cast<int>(std::lround(view.rowOfHeight(view.bustCm()) * ws));
  const int bustBand = static_cast<int>(std::lround(kShoulderBustBandCm * sw));
  if (bustRow <= 0 || bustRow + bustBand >= out.rows ||
      cv::countNonZero(closed.rowRange(bustRow, bustRow + bustBand + 1)) == 0)
    return out;
  // The torso's width at its first row below the armpit bounds the shoulders' columns (beyond it
  // the shoulder line is the arm's top edge, where a sleeve, not the bodice, goes on).
  std::optional<calib::RowSection> under;
  for (int row = static_cast<int>(std::lround(view.rowOfHeight(view.armpitCm())));
       row < view.size().height && !under; ++row)
    under = view.torsoAtRow(row);
  if (!under)
    return out;
  const int clear = std::max(1, static_cast<int>(std::lround(kClosureClearCm * sw)));
  cv::Mat formGrown;
  cv::dilate(formMask, formGrown,
             cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * clear + 1, 2 * clear + 1)));
  const cv::Mat outside = fgD & ~formGrown;
  const int reach = static_cast<int>(std::lround(kClosureReachCm * sw));
  const auto& outline = view.topOutline();
  const int from = std::max(0, static_cast<int>(std::lround(under->leftPx * ws)));
  const int to = std::min(out.cols - 1, static_cast<int>(std::lround(under->rightPx * ws)));
  for (int x = from; x <= to; ++x) {
    const auto full = static_cast<std::size_t>(std::lround(x / ws));
    if (full >= outline.size() || outline[full] < 0)
      continue;
    // The bare key's own top in this column, near the model's shoulder line.
    const int guess = static_cast<int>(std::lround(outline[full] * ws));
    int top = -1;
    for (int r = std::max(0, guess - reach); r <= std::min(bustRow, guess + reach) && top < 0; ++r)
      if (formMask.at<uchar>(r, x))
        top = r;
    if (top < 0 || top >= bustRow)
      continue;
    int above = -1;
    for (int r = std::max(0, top - clear - reach); r < top && above < 0; ++r)
      if (outside.at<uchar>(r, x))
        above = r;
    if (above < 0)
      continue;
    for (int r = above; r <= bustRow; ++r)
      if (fgD.at<uchar>(r, x))
        out.at<uchar>(r, x) = 255;
  }
  return out;
}

// The bare form's key, its inside (eroded by about 0.25 cm: the dressed frame cannot show screen
// there) and the ring round its outline where either key may place the edge.
struct FormBands {
  cv::Mat mask, inside, outline;
};

FormBands formBands(const cv::Mat& formMask, double sw) {
  FormBands bands{formMask, {}, {}};
  const int edgeR = std::max(1, static_cast<int>(std::lround(0.25 * sw)));
  cv::erode(formMask, bands.inside,
            cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * edgeR + 1, 2 * edgeR + 1)));
  cv::dilate(formMask, bands.outline, cv::Mat(), cv::Point(-1, -1), 2);
  bands.outline &= ~bands.inside;
  return bands;
}

// Both frames despilled over the same pixels, or the despill itself reads as a difference where
// one key missed part of the form (a dark green garment can cut the arms off the dressed key's
// main piece); returned as Lab.
std::pair<cv::Mat, cv::Mat> despilledLab(const calib::KeyResult& keyE,
                                         const calib::KeyResult& keyD) {
  cv::Mat1b both;
  const int band = calib::KeyOptions{}.edgeBandPx;
  cv::dilate(keyE.mask | keyD.mask, both,
             cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * band + 1, 2 * band + 1)));
  cv::Mat3b e = keyE.despilled.clone(), d = keyD.despilled.clone();
  calib::despill(e, both);
  calib::despill(d, both);
  cv::Mat labE, labD;
  cv::cvtColor(e, labE, cv::COLOR_BGR2Lab);
  cv::cvtColor(d, labD, cv::COLOR_BGR2Lab);
  return {labE, labD};
}

// The per-pixel difference of the two frames with the sensor noise, which differs between the
// shots, averaged away before thresholding: over the form only (the garment's shadow changes the
// screen beside it).
cv::Mat1f formDifference(const cv::Mat& labE, const cv::Mat& labD, const FormBands& form,
                         double sw) {
  cv::Mat1f diff = labDifference(labE, labD, form.outline);
  const int k = 2 * std::max(2, static_cast<int>(std::lround(0.3 * sw))) + 1;
  cv::Mat1f w, dw;
  form.mask.convertTo(w, CV_32F, 1.0 / 255.0);
  cv::GaussianBlur(diff.mul(w), dw, cv::Size(k, k), 0);
  cv::GaussianBlur(w, w, cv::Size(k, k), 0);
  return dw / cv::max(w, 1e-3f);
}

// Otsu's threshold of the difference over the form: the fallback noise threshold for a form with
// too little above its neck to read the noise floor there.
double otsuThresholdOverForm(const cv::Mat1f& diff, const cv::Mat& formMask, const cv::Mat& fgD) {
  cv::Mat d8;
  diff.convertTo(d8, CV_8U, 4.0);
  std::vector<uchar> values;
  for (int y = 0; y < d8.rows; y += 2)
    for (int x = 0; x < d8.cols; x += 2)
      if (formMask.at<uchar>(y, x) && fgD.at<uchar>(y, x))
        values.push_back(d8.at<uchar>(y, x));
  if (values.size() <= 100)
    return 10.0;
  cv::Mat v(values, false);
  cv::Mat dummy;
  return std::clamp(cv::threshold(v, dummy, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU) / 4.0, 5.0,
                    25.0);
}

struct ExposedForm {
  cv::Mat exposed;         // form that looks as in the bare frame
  cv::Mat clearlyExposed;  // well inside the noise: the form for certain near no garment
};

// Where the form is still visible the difference is noise; where the garment covers it, it is the
// garment's contrast. The noise floor is read where no garment goes: the form above its neck
// (head or neck cap). A pixel is exposed when its difference is within that noise, so a garment
// the colour of the form still stands out by its folds and weave.
ExposedForm exposedForm(const cv::Mat1f& diff, const cv::Mat& labE, const cv::Mat& labD,
                        const FormBands& form, const cv::Mat& fgD, const FormView& view,
                        const WorkGeometry& g, const cv::Mat& kernel) {
  const double ws = g.scale, sw = g.pxPerCm;
  const int neckRow =
      static_cast<int>(view.rowOfHeight(view.neckSideCm() + kNoiseAboveNeckCm) * ws);
  auto aboveNeck = [&](const cv::Mat1f& values) {
    std::vector<float> out;
    for (int y = 0; y < std::min(neckRow, values.rows); ++y)
      for (int x = 0; x < values.cols; x += 2)
        if (form.mask.at<uchar>(y, x) && fgD.at<uchar>(y, x))
          out.push_back(values(y, x));
    return out;
  };
  const std::vector<float> noise = aboveNeck(diff);
  const bool noiseKnown = noise.size() > 2000;
  const double tau = noiseKnown ? std::clamp(noiseThreshold(noise, kNoiseSigmas), 2.0, 25.0)
                                : otsuThresholdOverForm(diff, form.mask, fgD);
  // The form's outline counts as form out to where either key may place it (the two keys' edges
  // differ by a pixel with noise); there the difference is the shift-tolerant one.
  const cv::Mat formOrOutline = form.mask | form.outline;
  ExposedForm out;
  out.exposed = (diff < static_cast<float>(tau)) & formOrOutline & fgD;
  // Exposed well inside the noise (half the threshold, on both tests): the form for certain, up
  // to the blur's reach from the garment.
  out.clearlyExposed = (diff < static_cast<float>(kClearlyExposed * tau)) & out.exposed;
  if (noiseKnown) {
    // Of what looks exposed pixel by pixel, keep only what also matches over about a centimetre:
    // a garment the colour of the form differs there.
    const cv::Mat1f averaged = averagedDifference(
        labE, labD, form.inside, kAveragedDifferenceCm * sw, static_cast<float>(tau));
    const double tauAveraged = std::max(0.3, noiseThreshold(aboveNeck(averaged), kNoiseSigmas));
    out.exposed &= averaged < static_cast<float>(tauAveraged);
    out.clearlyExposed &= averaged < static_cast<float>(kClearlyExposed * tauAveraged);
  }
  cv::morphologyEx(out.exposed, out.exposed, cv::MORPH_CLOSE, kernel);
  out.exposed &= formOrOutline & fgD;
  return out;
}

// The garment's shadow on the form, which is not sure garment: it is GrabCut's to decide. A
// shadow is a smooth band that fades into the exposed form beside the garment: what looks like
// shadow is opened (a stripe or print of the garment shaded darker than the form is thin) and
// kept only where it touches the exposed form. Read with any chroma change up to a fifth of the
// darkening allowed (shallowFrom 0, the garment's bounce tints a shade). When most of what
// changed over the form looks like shadow so, the garment itself is dark, and only the shade that
// keeps the form's chroma in its deep part (kShadowShallow) is shadow; when most still looks like
// shadow, the garment is dark and neutral over a neutral form, and only shallow shade is (its
// L* + 16 at least kShadowShallow of the form's, shadowOnForm's shallowOnly): the shade of a
// near-black skirt on the thighs joined the skirt without it, and the skirt read as pants
// (fresh physical rig, seed 9494 case 5). When even that is most of the change, the garment is
// mid-grey over the form, and the test is not used (empty).
cv::Mat shadowBesideExposedForm(const cv::Mat& labE, const cv::Mat& labD, const FormBands& form,
                                const cv::Mat& fgD, const cv::Mat& exposed, double sw) {
  // The exposed form grown through the penumbra (dimmed by less than kShadowMinDarkening, chroma
  // kept) up to kShadowPenumbraCm: a long skirt's shade on the shins fades out over a centimetre
  // or two above the lit feet, and only touched the exposed form through that fade (physical
  // rig, 2 MP: the shins under a red skirt's hem were taken for garment).
  const ShadowFrames frames = shadowFrames(labE, labD, sw);
  const cv::Mat penumbra =
      (shadowOnForm(frames, form.inside, 0.5f, kShadowShallow) & fgD) | exposed;
  cv::Mat touching = exposed.clone();
  for (int i = 0; i < static_cast<int>(std::lround(kShadowPenumbraCm * sw)); ++i) {
    cv::dilate(touching, touching, cv::Mat());
    touching &= penumbra;
  }
  cv::dilate(touching, touching, cv::Mat(), cv::Point(-1, -1), 2);
  const double changedOverForm = cv::countNonZero(form.inside & fgD & ~exposed);
  const int rs = std::max(1, static_cast<int>(std::lround(kShadowMinWidthCm * sw / 2)));
  const cv::Mat open =
      cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * rs + 1, 2 * rs + 1));
  cv::Mat shadow;
  struct Pass {
    float shallowFrom;
    bool shallowOnly;
  };
  for (const Pass pass :
       {Pass{0.0f, false}, Pass{kShadowShallow, false}, Pass{kShadowShallow, true}}) {
    shadow =
        shadowOnForm(frames, form.inside, kShadowMinDarkening, pass.shallowFrom, pass.shallowOnly) &
        fgD & ~exposed;
    cv::morphologyEx(shadow, shadow, cv::MORPH_OPEN, open);
    cv::Mat labels;
    const int n = cv::connectedComponents(shadow, labels, 8, CV_32S);
    std::vector<uchar> keep(static_cast<std::size_t>(n), 0);
    for (int y = 0; y < labels.rows; ++y) {
      const int* l = labels.ptr<int>(y);
      const uchar* t = touching.ptr(y);
      for (int x = 0; x < labels.cols; ++x)
        if (l[x] > 0 && t[x])
          keep[static_cast<std::size_t>(l[x])] = 1;
    }
    for (int y = 0; y < labels.rows; ++y) {
      const int* l = labels.ptr<int>(y);
      uchar* m = shadow.ptr(y);
      for (int x = 0; x < labels.cols; ++x)
        m[x] = l[x] > 0 && keep[static_cast<std::size_t>(l[x])] ? 255 : 0;
    }
    if (cv::countNonZero(shadow) <= kShadowMaxShareOfChange * changedOverForm)
      return shadow;
  }
  shadow.setTo(0);
  return shadow;
}

// The form's outline ring (left out of shadowOnForm: its pixels mix form and screen and shift
// between the shots) beside the shade on the legs, below `fromRow`, is shade too: otherwise the
// ring along a shaded leg stays garment and GrabCut grows it into a strip down the leg's edge
// (physical rig, 2 MP: a 12 cm strip below a dark skirt's hem). Higher up a garment's own edge
// lies on the ring (a simulated gingham top lost its sides' squares).
void addOutlineBesideShade(cv::Mat& shadow, const FormBands& form, const cv::Mat& fgD,
                           const cv::Mat& exposed, double sw, int fromRow) {
  if (fromRow >= shadow.rows)
    return;
  const int ring = std::max(1, static_cast<int>(std::lround(0.25 * sw))) + 2;
  cv::Mat nearShadow;
  cv::dilate(shadow, nearShadow,
             cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * ring + 1, 2 * ring + 1)));
  cv::Mat add = nearShadow & form.outline & fgD & ~exposed;
  add.rowRange(0, std::max(0, fromRow)).setTo(0);
  shadow |= add;
}

// Where shade on the form can only be the garment's shadow, not the garment: below the crotch
// (the legs), and, for a garment that ends above the crotch (a top), above it below the lowest
// sure garment of a column that has some. Higher up, a near-black garment's lit folds look like
// the form's deep shade (physical rig case_005: with the rule over the whole form a patch of its
// skirt became sure form and the skirt read 41 cm short). Pants reach below the crotch: the
// shade-like top of the gap between a form-coloured pair's legs is theirs (simulated hard pants,
// seed 5: with the rule, the crotch read 5 cm high).
constexpr double kGarmentBelowCrotchCm2 = 4.0;

// A top's hem, column by column: the lowest sure garment within kHemNeighbourhoodCm to either
// side, of pieces of sure garment at least kHemPieceCm2 large. A patterned top's sure garment can
// be patchy (a dark green polka-dot print whose dark cloth reads as shade: simulated hard top,
// seed 5), and a column's own lowest sure pixel then lies far up inside the top while its
// neighbours' reach the hem. Specks of sure garment on the lower edge of the shade under a light
// top's hem (1-2 cm2, fresh physical rig seed 8686, case 004) are no hem.
constexpr double kHemNeighbourhoodCm = 5.0;
constexpr double kHemPieceCm2 = 10.0;

struct HemReading {
  double neighbourhoodCm = 0.0;  // columns to either side whose lowest sure garment counts
  double minPieceCm2 = 0.0;      // smaller pieces of sure garment are left out
};

std::vector<int> lowestSureNear(const cv::Mat& sure, double pxPerCm, const HemReading& how) {
  // Labelling the pieces costs a pass over the frame; only a minimum size needs it.
  cv::Mat pieces = sure;
  if (how.minPieceCm2 > 0) {
    cv::Mat labels, stats, centroids;
    const int n = cv::connectedComponentsWithStats(sure, labels, stats, centroids, 8, CV_32S);
    std::vector<uchar> keep(static_cast<std::size_t>(n), 0);
    for (int i = 1; i < n; ++i)
      keep[static_cast<std::size_t>(i)] =
          stats.at<int>(i, cv::CC_STAT_AREA) >= how.minPieceCm2 * pxPerCm * pxPerCm ? 255 : 0;
    pieces = cv::Mat(sure.size(), CV_8UC1);
    for (int y = 0; y < sure.rows; ++y) {
      const int* l = labels.ptr<int>(y);
      uchar* m = pieces.ptr(y);
      for (int x = 0; x < sure.cols; ++x)
        m[x] = keep[static_cast<std::size_t>(l[x])];
    }
  }
  std::vector<int> lowest(static_cast<std::size_t>(sure.cols), -1);
  for (int y = 0; y < pieces.rows; ++y) {
    const uchar* m = pieces.ptr(y);
    for (int x = 0; x < pieces.cols; ++x)
      if (m[x])
        lowest[static_cast<std::size_t>(x)] = y;
  }
  const int halfWidth = static_cast<int>(std::lround(how.neighbourhoodCm * pxPerCm));
  std::vector<int> near(lowest.size(), -1);
  for (int x = 0; x < sure.cols; ++x)
    for (int dx = std::max(0, x - halfWidth); dx <= std::min(sure.cols - 1, x + halfWidth); ++dx)
      near[static_cast<std::size_t>(x)] =
          std::max(near[static_cast<std::size_t>(x)], lowest[static_cast<std::size_t>(dx)]);
  return near;
}

// Rows below the crotch, and for a top (a garment that ends above the crotch) the rows from its
// hem (lowestSureNear, read as `how` says) down to the crotch; `topOnly` leaves out the rows below
// the crotch.
cv::Mat belowGarment(const cv::Mat& sure, int crotchRow, double pxPerCm, const HemReading& how,
                     bool topOnly) {
  cv::Mat out = cv::Mat::zeros(sure.size(), CV_8UC1);
  const int crotch = std::clamp(crotchRow, 0, sure.rows);
  if (!topOnly)
    out.rowRange(crotch, sure.rows).setTo(255);
  if (cv::countNonZero(sure.rowRange(crotch, sure.rows)) >
      kGarmentBelowCrotchCm2 * pxPerCm * pxPerCm)
    return out;
  const std::vector<int> hem = lowestSureNear(sure, pxPerCm, how);
  for (int x = 0; x < sure.cols; ++x) {
    const int lowest = hem[static_cast<std::size_t>(x)];
    if (lowest < 0)
      continue;
    for (int y = lowest + 1; y < crotch; ++y)
      out.at<uchar>(y, x) = 255;
  }
  return out;
}

struct SettledRegions {
  cv::Mat garment;  // probable garment too far from any exposed form for GrabCut to decide
  cv::Mat form;     // exposed form too far from any garment evidence to be garment
};

// GrabCut has a choice to make only near the exposed form: elsewhere the dressed foreground is
// garment up to the key's edge against the screen (placed again at full resolution later).
// Probable garment farther than kSettledCm from any exposed pixel is therefore sure, which leaves
// the band cut nothing to decide along the screen-facing outline. Likewise exposed form farther
// than kSettledCm from any garment evidence is sure form: a garment the colour of the form gives
// GrabCut's colour models nothing to tell them apart by, and it would otherwise flood the bare
// torso and arms from the garment.
SettledRegions settledRegions(const cv::Mat& fgD, const ExposedForm& form, const cv::Mat& shadow,
                              double sw) {
  SettledRegions out;
  cv::Mat1f distToExposed, distToGarment;
  cv::distanceTransform(~(form.exposed | shadow), distToExposed, cv::DIST_L2, cv::DIST_MASK_3);
  out.garment = (distToExposed > static_cast<float>(kSettledCm * sw)) & fgD;
  cv::distanceTransform(~(fgD & ~form.exposed), distToGarment, cv::DIST_L2, cv::DIST_MASK_3);
  out.form = ((distToGarment > static_cast<float>(kSettledCm * sw)) & form.exposed) |
             ((distToGarment > static_cast<float>(kClearlySettledCm * sw)) & form.clearlyExposed &
              form.exposed);
  return out;
}

// Intermediate masks for diagnosing segmentation, written when GARMCAP_DEBUG_DIR is set: trimap
// labels x 80, colour difference x 4, the exposed form, the shadow and the two keys' masks.
void writeDebugMasks(const GarmentMasks& masks, const cv::Mat1f& diff, const cv::Mat& shadow,
                     const cv::Mat& dressedKey) {
  const char* dir = std::getenv("GARMCAP_DEBUG_DIR");
  if (!dir)
    return;
  cv::imwrite(std::string(dir) + "/trimap.png", masks.trimap * 80);
  cv::Mat d8;
  diff.convertTo(d8, CV_8U, 4.0);
  cv::imwrite(std::string(dir) + "/diff.png", d8);
  cv::imwrite(std::string(dir) + "/exposed.png", masks.exposed);
  cv::imwrite(std::string(dir) + "/shadow.png", shadow);
  cv::imwrite(std::string(dir) + "/key_bare.png", masks.form);
  cv::imwrite(std::string(dir) + "/key_dressed.png", dressedKey);
}

}  // namespace

GarmentMasks garmentMasks(const calib::KeyResult& keyE, const calib::KeyResult& keyD,
                          const FormView& view, const WorkGeometry& g,
                          std::vector<std::string>& warnings) {
  const double ws = g.scale, sw = g.pxPerCm;
  const auto [labE, labD] = despilledLab(keyE, keyD);
  const FormBands form = formBands(keyE.mask, sw);
  const cv::Mat1f diff = formDifference(labE, labD, form, sw);
  // The form cannot vanish: inside it the dressed frame shows the form or the garment, whatever
  // the key says (a dark green garment keys as screen by its greenness). Its outline is left to
  // the key: mixed edge pixels differ between the shots by any sub-pixel shift.
  const cv::Mat fgD = keyD.mask | form.inside;
  const int r = std::max(2, static_cast<int>(std::lround(0.4 * sw)));
  const cv::Mat kernel =
      cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1));
  const ExposedForm exposed = exposedForm(diff, labE, labD, form, fgD, view, g, kernel);
  cv::Mat shadow = shadowBesideExposedForm(labE, labD, form, fgD, exposed.exposed, sw);
  const int crotchRow =
      view.crotchCm()
          ? std::clamp(static_cast<int>(std::lround(view.rowOfHeight(*view.crotchCm()) * ws)), 0,
                       fgD.rows)
          : fgD.rows;
  addOutlineBesideShade(shadow, form, fgD, exposed.exposed, sw, crotchRow);

  cv::Mat base = fgD & ~exposed.exposed & ~shadow;
  cv::morphologyEx(base, base, cv::MORPH_OPEN, kernel);
  cv::Mat sure;
  cv::erode(base, sure, kernel);
  if (cv::countNonZero(sure) < 0.002 * static_cast<double>(form.mask.total()) + 50 * ws * ws)
    throw CaptureError(
        CaptureError::Reason::kNoGarment,
        "no garment found: the dressed frame shows the bare form (is the garment on the form?)");

  GarmentMasks out;
  // A garment close to the screen's colour: GrabCut decides over the changed screen too.
  out.screenChange = screenColouredChange(keyE, keyD, form.inside, form.outline, fgD, sw, warnings);
  const ScreenChange screenChange =
      out.screenChange
          ? *out.screenChange
          : ScreenChange{cv::Mat::zeros(fgD.size(), CV_8UC1), cv::Mat::zeros(fgD.size(), CV_8UC1)};
  const SettledRegions settled = settledRegions(fgD, exposed, shadow, sw);
  cv::Mat& trimap = out.trimap;
  trimap = cv::Mat(fgD.size(), CV_8UC1, cv::Scalar(cv::GC_BGD + 0));
  trimap.setTo(cv::GC_PR_BGD + 0, screenChange.changed);
  trimap.setTo(cv::GC_PR_FGD + 0, screenChange.recoloured);
  trimap.setTo(cv::GC_PR_FGD + 0, fgD);
  trimap.setTo(cv::GC_FGD + 0, settled.garment);
  trimap.setTo(cv::GC_PR_BGD + 0, exposed.exposed | shadow);
  // Shade on the form lighter than most of the garment is sure form where it lies below the
  // garment (belowGarment): GrabCut's colour models take a dark skirt's shade on the thighs for
  // the skirt (physical rig, 2 MP: strips of thigh 12 cm long below a near-black skirt's hem), and
  // a knit top's shade under its hem for the top (fresh physical cases, seed 1515 and 7373: the
  // silhouette went 1-1.5 cm down into it at the centre, and the hem, read just above the
  // lowest row, 3.7-18 cm small). No fold of the garment is lighter than the garment's median. A
  // light garment's own folds can look like the form's shade (light yellow pants over a beige
  // form), and stay GrabCut's. Under a top's hem (lowestSureNear; above the crotch, for a garment
  // that ends above it) shade darker than nine tenths of the garment is sure form too: a light
  // top's shade on the form is darker than the top's folds but as dark as the form's shade
  // elsewhere, and GrabCut took it for the top (fresh physical rig, seed 8686: three light woven
  // tops on the ivory form read 4.6-4.8 cm long with their hems refused, a knit top's hem 8.5 cm
  // small; docs/measurement_model.md, "Shade under a light top's hem"). Without the darkness
  // condition a dark green polka-dot top, whose despilled cloth passes the shade test, lost
  // strips of its lower edge (simulated hard top, seed 5: hem 4-7 cm small). Cloth hanging beyond
  // both edges of a leg is still garment (closedAcrossForm, set after this).
  {
    std::vector<uchar> lightness;
    for (int y = 0; y < sure.rows; y += 2)
      for (int x = 0; x < sure.cols; x += 2)
        if (sure.at<uchar>(y, x))
          lightness.push_back(labD.at<cv::Vec3b>(y, x)[0]);
    if (!lightness.empty()) {
      auto mid = lightness.begin() + static_cast<long>(lightness.size() / 2);
      std::nth_element(lightness.begin(), mid, lightness.end());
      const uchar median = *mid;
      auto tenth = lightness.begin() + static_cast<long>(lightness.size() / 10);
      std::nth_element(lightness.begin(), tenth, mid);
      const uchar darkestTenth = *tenth;
      cv::Mat l;
      cv::extractChannel(labD, l, 0);
      const cv::Mat underTop =
          belowGarment(sure, crotchRow, sw, {kHemNeighbourhoodCm, kHemPieceCm2}, /*topOnly=*/true);
      const cv::Mat formShade =
          ((l > median) & belowGarment(sure, crotchRow, sw, {}, /*topOnly=*/false)) |
          ((l < darkestTenth) & underTop);
      trimap.setTo(cv::GC_BGD + 0, formShade & shadow & form.inside);
    }
  }
  trimap.setTo(cv::GC_BGD + 0, settled.form);
  trimap.setTo(cv::GC_FGD + 0, sure);
  const cv::Mat closed = closedAcrossForm(fgD, form.mask, view, ws, sw);
  const cv::Mat closedRows = closed == kClosedRow;
  trimap.setTo(cv::GC_FGD + 0, closedRows);
  trimap.setTo(cv::GC_PR_BGD + 0, (closed == kBetweenClosedRows) & (trimap == cv::GC_BGD));
  trimap.setTo(cv::GC_FGD + 0, coveredFromShoulders(fgD, form.mask, closedRows, view, ws, sw));
  out.form = form.mask;
  out.foreground = fgD;
  out.exposed = exposed.exposed;
  writeDebugMasks(out, diff, shadow, keyD.mask);
  return out;
}

}  // namespace garmcap::pipeline
