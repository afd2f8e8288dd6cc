#include "garmcap/pipeline/garment_measurer.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "frame_ops.h"
#include "garmcap/calib/slicer.h"
#include "garmcap/drafts/garment_vocabulary.h"
#include "garmcap/pipeline/section_perimeter.h"
#include "hem_band.h"

namespace garmcap::pipeline {
namespace {

using calib::RowSection;

// How far below a height hidden by sleeves a circumference may be read instead.
constexpr double kHiddenSearchCm = 6.0;
// Span of clear rows a hidden circumference is extrapolated from.
constexpr double kFitSpanCm = 4.0;
// Half-height of the band of rows averaged for a circumference: inside the ±1.5 cm the garment
// keeps its circumference around a measured height (docs/measurement_model.md).
constexpr double kBandCm = 1.0;
// Between waist and armpit a bodice's side moves out by well under half a centimetre per
// centimetre of height; a side this much further out than 1 cm lower is a sleeve hanging over
// it (a short, wide sleeve droops below the armpit in an A-pose).
constexpr double kSleeveStepCm = 0.6;
// Hem circumference is read this far above the hem edge.
constexpr double kAboveHemCm = 1.25;
// Legs that part this far below the form's crotch touch above (crotchHeightCm), and the gap
// between them is fitted over this height.
constexpr double kTouchingLegsCm = 5.5;
constexpr double kGapFitCm = 8.0;
// Legs narrower than this share of the garment kLegStepCm above where they part are no pants'
// legs (partedLegsCm).
constexpr double kLegStepShare = 0.8;
constexpr double kLegStepCm = 1.0;
// A pants leg's hem: its run across the leg narrows by no more than this share within this
// height (legHemRow).
constexpr double kHemTailShare = 0.6;
constexpr double kHemTailCm = 4.0;
// A pants leg whose inner edge at its opening lies closer than this to the centre line is
// pressed against the other leg (legOpeningCm); touching legs meet at the centre line, and the
// slit between them is carved +-0.5 cm around it (leg_gap.h).
constexpr double kPressedLegGapCm = 1.0;
// A free trouser leg hangs as a tube flattened front to back, this deep for its width at its
// opening: the mean of the physical rig's free straight legs measured on their settled cloth
// (tests/data/rig_physical case_002 14.6 / 16.3 and 14.7 / 16.5, case_017 14.0 / 16.8 and
// 15.3 / 15.5 cm; docs/measurement_model.md, "Leg openings that hang from the knee" and "A free
// leg hangs flattened").
constexpr double kFreeLegDepthShare = 0.9;
// The garment's top is read this far outside the form's neck (see garment_length).
constexpr double kOutsideNeckCm = 0.5;
// A top's hem's width is read over this height above its centre-front row (frontHemHeightCm).
constexpr double kHemWidthBandCm = 6.0;
// A hem whose cloth goes on more than kHemLevelDropCm below where the garment's full width ends
// is not level (hemLevel): a check. What hangs below lies to one side when its mean column is
// more than kHemSlantShare of the hem's width off the centre line (asymmetric: 0.18-0.19 on two
// physical skirts), else at the centre (high-low: 0.03).
constexpr double kHemLevelDropCm = 4.0;
constexpr double kHemSlantShare = 0.1;
constexpr double kHemFullShare = 0.9;
constexpr double kHemCoverShare = 0.35;
constexpr double kHemLevelSearchCm = 10.0;
constexpr double kHemLevelMinCm = 8.0;
// A dark band deeper than this above a skirt's or dress's lowest edge is a high-low hem's back
// seen under its front (darkBandAboveHem; see the hem in measureGarment).
constexpr double kHemBandCheckCm = 3.0;
// The form's shoulder ridge beside the neck (shoulderRidgeZ): its surface below the side neck
// plus kRidgeHeadCm, the highest kRidgeBandCm of it in a column.
constexpr double kRidgeHeadCm = 2.0;
constexpr double kRidgeBandCm = 0.5;
// Gaps bridged in the garment's cover of a column beside the neck (garmentTopRow).
constexpr double kTopGapCm = 0.5;
// A skirt's waistband can sit this far below the form's waist at the centre front (the hem is
// followed down from the first covered row).
constexpr double kWaistbandDropCm = 3.0;
// Gaps in a mask run up to this many pixels are bridged (GrabCut specks, printed motifs).
constexpr int kMaxGapPx = 2;
// A piece of garment this close beyond a torso row's run is the garment's own side, cut off by a
// pattern square the segmentation took for screen (readRow).
constexpr double kSidePieceGapCm = 0.75;

// The run of set pixels in `row` that contains `col` (gaps of kMaxGapPx bridged), as
// [left edge, right edge] in pixel-edge coordinates; nullopt when `col` is not set.
std::optional<std::pair<double, double>> runAt(const cv::Mat& mask, int row, int col,
                                               int limitLeft = -1, int limitRight = -1) {
  if (row < 0 || row >= mask.rows)
    return std::nullopt;
  if (!maskCovers(mask, row, col)) {
    // Allow the centre to sit in a tiny gap.
    int c = -1;
    for (int d = 1; d <= kMaxGapPx && c < 0; ++d) {
      if (maskCovers(mask, row, col - d))
        c = col - d;
      else if (maskCovers(mask, row, col + d))
        c = col + d;
    }
    if (c < 0)
      return std::nullopt;
    col = c;
  }
  const int lo = limitLeft >= 0 ? limitLeft : 0;
  const int hi = limitRight >= 0 ? std::min(limitRight, mask.cols - 1) : mask.cols - 1;
  int l = col, r = col;
  for (int x = col - 1; x >= lo; --x) {
    if (maskCovers(mask, row, x))
      l = x;
    else if (col - x > 0 && l - x > kMaxGapPx)
      break;
  }
  for (int x = col + 1; x <= hi; ++x) {
    if (maskCovers(mask, row, x))
      r = x;
    else if (x - r > kMaxGapPx)
      break;
  }
  return std::make_pair(static_cast<double>(l), static_cast<double>(r + 1));
}

// The run at `row` through `col` (runAt), widened across holes inside the form's own section
// `torso`: garment on both sides of the centre within the form's edges is one garment, a tube
// round the form, and a hole between is a patch the segmentation lost (a light fabric over a
// light form matches the bare frame there: a physical rig's white knit top read its bust 28 cm
// round from the piece of its run left at the centre). The run may start at either side of the
// hole when the centre itself is in it.
std::optional<std::pair<double, double>> runAcrossForm(const cv::Mat& mask, int row, int col,
                                                       const RowSection& torso, int limitLeft,
                                                       int limitRight) {
  auto run = runAt(mask, row, col, limitLeft, limitRight);
  if (row < 0 || row >= mask.rows)
    return run;
  const int lo = std::max({0, static_cast<int>(std::ceil(torso.leftPx)), limitLeft});
  const int hi = std::min({mask.cols - 1, static_cast<int>(std::floor(torso.rightPx)) - 1,
                           limitRight >= 0 ? limitRight : mask.cols - 1});
  const uchar* m = mask.ptr(row);
  int first = -1, last = -1;
  for (int x = lo; x <= hi; ++x)
    if (m[x]) {
      first = first < 0 ? x : first;
      last = x;
    }
  if (first < 0 || first >= col || last <= col)
    return run;  // garment on one side of the centre only: no tube to close
  const auto left = runAt(mask, row, first, limitLeft, limitRight);
  const auto right = runAt(mask, row, last, limitLeft, limitRight);
  if (!left || !right)
    return run;
  double l = left->first, r = right->second;
  if (run) {
    l = std::min(l, run->first);
    r = std::max(r, run->second);
  }
  return std::make_pair(l, r);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// ---- The hanging-depth section model (docs/measurement_model.md, "Section depth") ----

// The form's torso sections every kDepthStepCm from just above the crotch (or the form's
// lowest torso section) to the armpit: each one's convex hull (x, z in cm). Slicing the
// mesh costs about a millisecond a section, so the table is made once per form and kept.
constexpr double kDepthStepCm = 1.0;

struct DepthTable {
  double firstCm = 0;  // height of sample 0
  std::vector<std::vector<Eigen::Vector2d>> hulls;
};

// Width (x extent), depth (z extent) and convex-hull perimeter of a set of hull points, cm.
struct SectionShape {
  double widthCm = 0, depthCm = 0, circCm = 0;
};

SectionShape shapeOf(const std::vector<Eigen::Vector2d>& hull) {
  SectionShape s;
  if (hull.empty())
    return s;
  double x0 = hull[0].x(), x1 = x0, z0 = hull[0].y(), z1 = z0;
  for (const auto& p : hull) {
    x0 = std::min(x0, p.x());
    x1 = std::max(x1, p.x());
    z0 = std::min(z0, p.y());
    z1 = std::max(z1, p.y());
  }
  s.widthCm = x1 - x0;
  s.depthCm = z1 - z0;
  s.circCm = calib::polygonPerimeter(hull);
  return s;
}

std::shared_ptr<const DepthTable> depthTable(const FormView& view) {
  const calib::FormModel& form = view.form();
  // Keyed by what identifies a loaded form, by value: a capture may hold its own copy of the
  // form (another address, the same mesh), and a new form at an old address differs in these.
  struct Key {
    std::size_t vertices, triangles;
    double minY, maxY, axisX, axisZ, armpit, sample;
    bool operator==(const Key&) const = default;
  };
  const auto& vs = form.mesh().vertices;
  double sample = 0;  // a fingerprint of the vertices: 64 of them, spread over the mesh
  for (std::size_t i = 0; i < vs.size(); i += std::max<std::size_t>(1, vs.size() / 64))
    sample += vs[i].x() + 3.0 * vs[i].y() + 7.0 * vs[i].z();
  const Key key{vs.size(),      form.mesh().faces.size(), form.minYCm(),   form.maxYCm(),
                form.axisXCm(), form.axisZCm(),           view.armpitCm(), sample};
  static std::mutex mutex;
  static std::vector<std::pair<Key, std::shared_ptr<const DepthTable>>> cache;
  {
    const std::lock_guard lock(mutex);
    for (const auto& [k, t] : cache)
      if (k == key)
        return t;
  }
  auto table = std::make_shared<DepthTable>();
  const double lo = view.crotchCm() ? *view.crotchCm() + 0.5 : view.hipCm() - 25.0;
  table->firstCm = lo;
  for (double h = lo; h <= view.armpitCm() + 1e-9; h += kDepthStepCm) {
    const calib::FormSection sec = form.section(h);
    table->hulls.push_back(sec.torsoLoops.empty() ? std::vector<Eigen::Vector2d>{}
                                                  : calib::convexHull(sec.torsoLoops));
  }
  const std::lock_guard lock(mutex);
  if (cache.size() >= 8)
    cache.erase(cache.begin());
  cache.emplace_back(key, table);
  return table;
}

// The envelope of the form's torso sections from loCm up to hiCm: the convex hull of all their
// points, seen from the front (width) and the side (depth).
SectionShape envelopeOf(const DepthTable& t, double loCm, double hiCm) {
  std::vector<Eigen::Vector2d> pts;
  for (std::size_t i = 0; i < t.hulls.size(); ++i) {
    const double h = t.firstCm + static_cast<double>(i) * kDepthStepCm;
    if (h >= loCm - 0.5 * kDepthStepCm && h <= hiCm + 0.5 * kDepthStepCm)
      pts.insert(pts.end(), t.hulls[i].begin(), t.hulls[i].end());
  }
  if (pts.size() < 3)
    return {};
  return shapeOf(calib::convexHull({pts}));
}

SectionShape sectionOf(const DepthTable& t, double hCm) {
  if (t.hulls.empty())
    return {};
  const auto i = static_cast<std::size_t>(std::clamp(std::lround((hCm - t.firstCm) / kDepthStepCm),
                                                     0L, static_cast<long>(t.hulls.size()) - 1));
  return shapeOf(t.hulls[i]);
}

// A bodice's section at the bust is round out to the envelope of the form's sections up to the
// armpit grown by this much a side (a fitted bodice's ease, half kBustDepthEaseCm); what its
// sides stand out beyond that are fins (physical rigs, four of them, two fresh: loose tops'
// busts read 3-6.6 cm large as wider ellipses; docs/measurement_model.md, "A loose bodice's
// sides are fins").
constexpr double kBustRoundEaseCm = 0.5;

// The bust: a bodice is at most this much deeper than the envelope of the form's sections from
// the bust to the armpit (twice a fitted bodice's ease; physical rig, even cases: 0.5-1.5 cm
// tried, 1.14 / 2.91 cm mean / max at 1.0 against 2.17 / 6.22 for the similar section).
constexpr double kBustDepthEaseCm = 1.0;
// Below the bust a bodice hangs from it: its depth moves this share of the way from the form's
// section grown by its ease to the envelope of the sections up to the armpit (physical rig,
// even cases, tops' and dresses' waists and tops' hems: 0.2-0.5 all read 0.82-0.89 cm mean).
constexpr double kBodiceHangShare = 0.3;
// A skirt's hem: its sides swing out this far beyond the hip's width before the hem grows in
// depth (an H-line hem keeps the hip's depth; physical rig, even cases, 0-6 cm tried).
constexpr double kHemSideSwingCm = 3.0;
// A dress's hem hangs from its bodice, not from a waistband on the hip: its front falls from the
// bust and its back from the shoulder blades and seat, so it is deeper than a skirt's hem of the
// same width by this share of what the envelope of the form's sections from the hip to the bust
// is deeper than the hip (docs/measurement_model.md, "A dress's hem hangs from its bodice"; the
// committed full-form and torso rigs' dresses, 0.1-0.25 tried, flat from 0.1 to 0.2: their hems
// read 2.1 cm small on average by the skirt's rule where their skirts read 0.3 cm large).
constexpr double kDressHemHangShare = 0.15;

// A sleeveless bodice's waist: only a share of the ease it has there shows at its sides, the rest
// hangs in front and behind (nothing holds its sides out, as a sleeve does; the physical rigs'
// sleeveless wovens on the full form stand 1.0-1.8 cm off the form's waist at each side with
// 16-25 cm of ease; docs/measurement_model.md, "A sleeveless bodice's waist hangs"). On a form
// with arms, chosen on the committed full-form rig, where 0.5 reads its five sleeveless waists
// within 2.9 cm (they read 2.0-10.5 cm small by the bodice rule); a fresh full-form rig would
// take 0.4-0.45 (at 0.5 its worst is 5.9 cm small, from 13.3): a front view does not know this
// depth. On an armless torso form the sides stand out further for the same ease (a fresh torso
// rig read its dresses 13-15 cm large at 0.5): the committed torso rig's tops' and dresses'
// median share, 0.68, rounded (a fresh torso rig's median is 0.73).
constexpr double kSleevelessSideShare = 0.5;
constexpr double kArmlessSideShare = 0.7;

// Which rule gives a garment's section its depth (docs/measurement_model.md, "Section depth").
enum class DepthRule {
  kSimilar,         // the form's section scaled (a waistband)
  kEase,            // the form's section grown by a uniform ease: depth + (w - W)
  kBust,            // kEase, at most the bust-to-armpit envelope's depth + kBustDepthEaseCm
  kBodice,          // kEase moved kBodiceHangShare towards the envelope's depth up to the armpit
  kHem,             // at least the hip's depth; beyond kHemSideSwingCm, the hip section scaled;
                    // a dress's hem deeper by hemHangCm
  kSidesShowShare,  // no ellipse: sidesShare of the ease shows as width (a sleeveless bodice's
                    // waist)
};

// What the measurer takes a garment's section at one height to be: an ellipse as wide as the
// silhouette, its depth from the form by `rule`. `form` is the form's own section at the
// reference height, `hang` the envelope of the sections the garment hangs from.
struct DepthModel {
  DepthRule rule = DepthRule::kSimilar;
  SectionShape form, hang;
  // A floor on the depth of a section wider than the form (0: none): a loose top's hem hangs
  // from the form's sections above it (loosenHemDepth).
  double minDepthCm = 0;
  double sidesShare = 1.0;  // kSidesShowShare: the share of the ease that shows as width
  double hemHangCm = 0;     // kHem: what a dress's hem hangs deeper than a skirt's
  double depthFor(double widthCm) const {
    const double scaled = form.depthCm * widthCm / form.widthCm;
    if (widthCm <= form.widthCm || rule == DepthRule::kSimilar)
      return scaled;  // tighter than the form (a knit): its shape
    return std::max(minDepthCm, ruleDepth(widthCm));
  }
  double ruleDepth(double widthCm) const {
    const double scaled = form.depthCm * widthCm / form.widthCm;
    const double eased = form.depthCm + (widthCm - form.widthCm);
    switch (rule) {
      case DepthRule::kEase:
        return eased;
      case DepthRule::kBust:
        return std::min(eased, hang.depthCm + kBustDepthEaseCm);
      case DepthRule::kBodice:
        // Never more than its width's ease: with little ease a bodice lies on the form.
        return eased + std::min(kBodiceHangShare * std::max(0.0, hang.depthCm - eased),
                                widthCm - form.widthCm);
      case DepthRule::kHem:
        return std::max(form.depthCm, form.depthCm * (widthCm - kHemSideSwingCm) / form.widthCm) +
               hemHangCm;
      case DepthRule::kSidesShowShare:  // circFor reads it without a depth; as wide as eased
        return eased;
      case DepthRule::kSimilar:
        break;
    }
    return scaled;
  }
  // Circumference for a silhouette `ratio` times as wide as the form's section whose tape is
  // formCircCm: the form's tape times the two ellipses' perimeters' ratio, so that a garment as
  // wide as the form reads the form's tape and kSimilar reads what the similar section reads.
  double circFor(double ratio, double formCircCm) const {
    const double w = form.widthCm * ratio;
    // The sides stand (w - W) / 2 off the form, a uniform ease's perimeter 2 pi of that a side,
    // which is sidesShare of the whole ease.
    if (rule == DepthRule::kSidesShowShare && w > form.widthCm)
      return formCircCm + std::numbers::pi * (w - form.widthCm) / sidesShare;
    return formCircCm * ellipsePerimeter(w, depthFor(w)) /
           ellipsePerimeter(form.widthCm, form.depthCm);
  }
  // The same for sides standing shareLeft and shareRight of the form's half-width beyond it,
  // read as a round section out to the envelope `hang` grown by kBustRoundEaseCm and, beyond
  // that, a fin at each side (finHullGain; docs/measurement_model.md, "A loose bodice's sides
  // are fins").
  double circWithFins(double shareLeft, double shareRight, double formCircCm) const {
    const double half = 0.5 * form.widthCm;
    const double roundCm = std::max(0.0, 0.5 * (hang.widthCm - form.widthCm)) + kBustRoundEaseCm;
    const double sideL = shareLeft * half, sideR = shareRight * half;
    // A side inside the form's edge (a knit with negative ease) reads as the narrower section.
    const double roundL = std::min(sideL, roundCm), roundR = std::min(sideR, roundCm);
    const double w = form.widthCm + roundL + roundR, d = depthFor(w);
    const double p = ellipsePerimeter(w, d) + finHullGain(w, d, sideL - roundL) +
                     finHullGain(w, d, sideR - roundR);
    return formCircCm * p / ellipsePerimeter(form.widthCm, form.depthCm);
  }
};

struct Context {
  const cv::Mat& mask;
  const FormView& view;
  double s;  // px per cm
  GarmentMeasurement& out;
  std::string type;
  const DepthModel* depth = nullptr;  // nullptr: the similar-section model
  double sleevelessShare = 0;  // a sleeveless top's or dress's kSidesShowShare share; 0: none
};

// Whether the form at `heightCm` is inside the frame; when the frame cuts the form above it (a
// station framing the garment, the legs below the frame), a warning names the measurement and
// the landmark it needs, and the measurement is not made: it is never guessed from what is not
// seen.
bool formInFrame(Context& c, double heightCm, const std::string& measurement,
                 const std::string& landmark) {
  const double row = c.view.rowOfHeight(heightCm);
  if (row >= 0 && row < c.mask.rows)
    return true;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.1f", heightCm);
  c.out.warnings.push_back(
      measurement + ": the form's " + landmark + " (" + buf + " cm) is outside the frame (" +
      (row < 0 ? "above its top" : "below its bottom") + " edge); not measured");
  return false;
}

// Reference section for a height: the torso there, or the hip section below the hip.
std::optional<RowSection> referenceAt(const FormView& view, double heightCm) {
  return view.torsoAtHeight(std::max(heightCm, view.hipCm()));
}

// Columns the body's run may not pass: the inner edges of the form's arms at `row` (so a sleeve
// that touches the bodice is not counted as body width).
std::pair<int, int> armLimits(const FormView& view, int row, const RowSection& torso) {
  int left = 0, right = view.size().width - 1;
  const float* cov = view.coverage().ptr<float>(row);
  for (int x = static_cast<int>(torso.leftPx) - 2; x >= 0; --x)
    if (cov[x] > 0.5f) {
      left = x + 1;
      break;
    }
  for (int x = static_cast<int>(torso.rightPx) + 2; x < view.size().width; ++x)
    if (cov[x] > 0.5f) {
      right = x - 1;
      break;
    }
  return {left, right};
}

// One row's reading: the circumference by the section model (c.depth), the garment's edges, and
// the form's torso edges there (when the row crosses the torso).
struct RowValue {
  double circCm;
  cv::Point2d left, right;
  std::optional<RowSection> torso;
};

// The circumference read at one row; nullopt where the garment is absent. `hidden` is set where
// the run reaches the arm, or where, between waist and armpit, its side lies more than
// kSleeveStepCm further out than 1 cm lower (a sleeve hanging over the side).
std::optional<RowValue> readRow(const Context& c, int row, bool& hidden) {
  hidden = false;
  if (row < 0 || row >= c.mask.rows)
    return std::nullopt;
  const double h = c.view.heightOfRow(row);
  const auto section = referenceAt(c.view, h);
  if (!section)
    return std::nullopt;
  const auto torsoHere = c.view.torsoAtRow(row);
  int limL = -1, limR = -1;
  if (torsoHere && h < c.view.armpitCm())
    std::tie(limL, limR) = armLimits(c.view, row, *torsoHere);
  const int centreCol = static_cast<int>(std::lround(section->centrePx()));
  // Below the torso a skirt or dress is still one tube, round both legs: garment on both sides
  // of the centre within the hip's width is one garment, and a slit between is what the
  // segmentation lost there (a near-screen-coloured hem over the screen between the legs: rig N
  // case_010 and rig H case_005 read their hems from one side of a notch 0.1-1 cm wide, 13 and
  // 81 cm round), or a front slit, which does not shorten the hem either. A pair of pants'
  // legs are apart there.
  const bool tube = c.type == "skirt" || c.type == "dress";
  auto run = torsoHere ? runAcrossForm(c.mask, row, centreCol, *torsoHere, limL, limR)
             : tube    ? runAcrossForm(c.mask, row, centreCol, *section, limL, limR)
                       : runAt(c.mask, row, centreCol, limL, limR);
  if (!run)
    return std::nullopt;
  // From the waist's band down, a row's run goes on across a gap of up to kSidePieceGapCm to
  // garment beyond it, within the arm's limits: rig H case_013, a green check, had squares at its
  // left side taken for screen over 9 of the waist band's 15 rows, leaving the side's own cloth
  // 0.4-0.6 cm off the run (its waist 3.3 cm small). Not higher up: there a sleeve hangs close
  // beside the bodice (bridged, the bust read up to 0.6 cm larger on rigs H and N).
  if (torsoHere && h <= c.view.waistCm() + kBandCm) {
    const int gap = static_cast<int>(std::lround(kSidePieceGapCm * c.s));
    const int lo = limL >= 0 ? limL : 0;
    const int hi = limR >= 0 ? std::min(limR, c.mask.cols - 1) : c.mask.cols - 1;
    for (bool grown = true; grown;) {
      const double l0 = run->first, r0 = run->second;
      const int l = static_cast<int>(l0), r = static_cast<int>(r0) - 1;
      for (int x = l - 1; x >= std::max(lo, l - 1 - gap); --x)
        if (maskCovers(c.mask, row, x)) {
          if (const auto piece = runAt(c.mask, row, x, limL, limR))
            run->first = std::min(run->first, piece->first);
          break;
        }
      for (int x = r + 1; x <= std::min(hi, r + 1 + gap); ++x)
        if (maskCovers(c.mask, row, x)) {
          if (const auto piece = runAt(c.mask, row, x, limL, limR))
            run->second = std::max(run->second, piece->second);
          break;
        }
      grown = run->first < l0 || run->second > r0;
    }
  }
  hidden = (limL >= 0 && run->first <= limL) || (limR >= 0 && run->second >= limR + 1);
  if (!hidden && torsoHere && h < c.view.armpitCm() && h > c.view.waistCm()) {
    const int below = row + static_cast<int>(std::lround(c.s));
    const auto torsoBelow = c.view.torsoAtRow(below);
    int bl = -1, br = -1;
    if (torsoBelow)
      std::tie(bl, br) = armLimits(c.view, below, *torsoBelow);
    const auto runBelow = torsoBelow ? runAcrossForm(c.mask, below, centreCol, *torsoBelow, bl, br)
                                     : runAt(c.mask, below, centreCol, bl, br);
    const double step = kSleeveStepCm * c.s;
    hidden =
        runBelow && (runBelow->first - run->first > step || run->second - runBelow->second > step);
  }
  const double ratio = (run->second - run->first) / section->widthPx();
  return RowValue{c.depth ? c.depth->circFor(ratio, section->circCm) : section->circCm * ratio,
                  {static_cast<double>(run->first), static_cast<double>(row)},
                  {static_cast<double>(run->second), static_cast<double>(row)},
                  torsoHere};
}

// Circumference at form height h by the section model (c.depth), median over a band of rows.
// Rows where the garment runs into the form's arm are left out: there a sleeve lying on the
// bodice hides the body's side seam, and the run holds sleeve and the gap to the arm. When the
// whole band is hidden so, the nearest rows below it (up to kHiddenSearchCm) that show the side
// stand in, and a warning says how far below.
std::optional<double> circumferenceReading(Context& c, double heightCm, const std::string& name) {
  const auto ref = referenceAt(c.view, heightCm);
  if (!ref || ref->widthPx() <= 1 || ref->circCm <= 0)
    return std::nullopt;
  const int r0 = static_cast<int>(std::lround(c.view.rowOfHeight(heightCm + kBandCm)));
  const int r1 = static_cast<int>(std::lround(c.view.rowOfHeight(heightCm - kBandCm)));
  std::vector<RowValue> clear;
  int covered = 0;
  for (int row = r0; row <= r1; ++row) {
    bool hidden = false;
    const auto v = readRow(c, row, hidden);
    if (!v)
      continue;
    ++covered;
    if (!hidden)
      clear.push_back(*v);
  }
  if (covered < 2) {
    c.out.warnings.push_back(name + ": the garment does not cover the form at " +
                             std::to_string(static_cast<int>(std::lround(heightCm))) + " cm");
    return std::nullopt;
  }
  if (clear.size() < 2) {
    // Hidden band: fit a line C(h) over the clear rows just below it (up to kFitSpanCm of
    // them). The bust is where a top is widest between shoulder and waist, so C(h) is taken as
    // a parabola with its top at the bust, C_b - k (h_b - h)^2: the line is its tangent at the
    // window's centre h_c, and C_b = C(h_c) + slope (h_b - h_c) / 2 (a straight extrapolation
    // overshoots by as much as the nearest row falls short). A garment that widens downward
    // has no such top; it gets the nearest clear row's value.
    clear.clear();
    std::vector<double> heights;
    const int rLimit =
        static_cast<int>(std::lround(c.view.rowOfHeight(heightCm - kHiddenSearchCm)));
    double firstClearH = 0;
    for (int row = r1 + 1; row <= rLimit; ++row) {
      bool hidden = false;
      const auto v = readRow(c, row, hidden);
      const double h = c.view.heightOfRow(row);
      if (v && !hidden) {
        if (clear.empty())
          firstClearH = h;
        if (firstClearH - h > kFitSpanCm)
          break;
        clear.push_back(*v);
        heights.push_back(h);
      } else if (!clear.empty()) {
        break;  // one run of clear rows, the nearest
      }
    }
    if (clear.size() < 3) {
      c.out.warnings.push_back(name + ": sleeves cover the garment's sides at " +
                               std::to_string(static_cast<int>(std::lround(heightCm))) +
                               " cm and below; not measured");
      return std::nullopt;
    }
    Eigen::MatrixXd a(static_cast<Eigen::Index>(clear.size()), 2);
    Eigen::VectorXd b(static_cast<Eigen::Index>(clear.size()));
    for (std::size_t i = 0; i < clear.size(); ++i) {
      a(static_cast<Eigen::Index>(i), 0) = 1.0;
      a(static_cast<Eigen::Index>(i), 1) = heights[i] - heightCm;
      b(static_cast<Eigen::Index>(i)) = clear[i].circCm;
    }
    const Eigen::Vector2d fit = a.colPivHouseholderQr().solve(b);
    double hCentre = 0;
    for (const double h : heights)
      hCentre += h;
    hCentre /= static_cast<double>(heights.size());
    const double slope = fit(1);  // cm of circumference per cm of height (up)
    const double atCentre = fit(0) + slope * (hCentre - heightCm);
    const double estimate =
        slope > 0 ? atCentre + 0.5 * slope * (heightCm - hCentre) : clear.front().circCm;
    const double below = heightCm - firstClearH;
    c.out.warnings.push_back(name + ": sleeves cover the sides at the " +
                             name.substr(0, name.find("_circ")) + "; estimated from " +
                             std::to_string(static_cast<int>(std::lround(below))) +
                             " cm lower, where the sides show");
    const std::string base = name.substr(0, name.find("_circ"));
    c.out.landmarks.push_back({base + "_left", clear.front().left});
    c.out.landmarks.push_back({base + "_right", clear.front().right});
    return estimate;
  }
  std::vector<double> values;
  for (const auto& v : clear)
    values.push_back(v.circCm);
  const std::string base = name.substr(0, name.find("_circ"));
  c.out.landmarks.push_back({base + "_left", clear.back().left});
  c.out.landmarks.push_back({base + "_right", clear.back().right});
  return median(values);
}

// Linear-interpolated quantile q (0..1) of a non-empty sample.
double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto i = static_cast<std::size_t>(std::floor(pos));
  const std::size_t j = std::min(i + 1, v.size() - 1);
  return v[i] + (pos - static_cast<double>(i)) * (v[j] - v[i]);
}

// The bust from the garment's side offsets (docs/measurement_model.md, "The bust's sides").
// Just below the armhole the cloth of a bodice folds: a sleeveless cut's underarm and a sleeve's
// underarm hang outside the side for a few cm, as a thin fin that adds much width and little to
// the section's round (physical rig: a knit top 2.8 cm beyond the form on each side at the bust,
// 0.8-1.3 cm 3-5 cm lower, its ease). So each side's offset beyond the form's torso edge, as a
// share of the form's half-width at its row, is collected over kBustSideBandCm worth of clear
// rows from the bust down (rows hidden by the arm or a sleeve are skipped, down to
// kHiddenSearchCm + kBandCm below the bust), and its lower tenth taken: a fold is a local bump
// in that profile, a bodice's side is its floor. The share carries over to the bust's own
// section as its width (1 + share times the form's), which the section model (c.depth, the bust's
// rule) turns into a round. A warning says when the rows reached further down than the band.
constexpr double kBustSideBandCm = 3.0;
constexpr double kBustSideQuantile = 0.1;

std::optional<double> bustFromSides(Context& c, double heightCm, const std::string& name) {
  const auto ref = referenceAt(c.view, heightCm);
  if (!ref || ref->widthPx() <= 1 || ref->circCm <= 0)
    return std::nullopt;
  const int r0 = static_cast<int>(std::lround(c.view.rowOfHeight(heightCm)));
  const int rLimit =
      static_cast<int>(std::lround(c.view.rowOfHeight(heightCm - kHiddenSearchCm - kBandCm)));
  const auto wanted = static_cast<std::size_t>(std::max(3.0, std::round(kBustSideBandCm * c.s)));
  std::vector<double> left, right;
  int covered = 0, lastRow = r0;
  for (int row = r0; row <= rLimit && left.size() < wanted; ++row) {
    bool hidden = false;
    const auto v = readRow(c, row, hidden);
    if (!v)
      continue;
    ++covered;
    if (hidden || !v->torso || v->torso->widthPx() <= 1)
      continue;
    const double half = 0.5 * v->torso->widthPx();
    left.push_back((v->torso->leftPx - v->left.x) / half);
    right.push_back((v->right.x - v->torso->rightPx) / half);
    lastRow = row;
  }
  if (covered < 2) {
    c.out.warnings.push_back(name + ": the garment does not cover the form at " +
                             std::to_string(static_cast<int>(std::lround(heightCm))) + " cm");
    return std::nullopt;
  }
  if (left.size() < 3) {
    c.out.warnings.push_back(name + ": sleeves cover the garment's sides at " +
                             std::to_string(static_cast<int>(std::lround(heightCm))) +
                             " cm and below; not measured");
    return std::nullopt;
  }
  const double lowestCm = heightCm - c.view.heightOfRow(lastRow);
  if (lowestCm > kBustSideBandCm + 0.5)
    c.out.warnings.push_back(
        name + ": sleeves cover the sides at the bust; read from the sides down to " +
        std::to_string(static_cast<int>(std::lround(lowestCm))) + " cm lower, where they show");
  const double shareLeft = quantile(left, kBustSideQuantile);
  const double shareRight = quantile(right, kBustSideQuantile);
  const double half = 0.5 * ref->widthPx();
  const double row = c.view.rowOfHeight(heightCm);
  c.out.landmarks.push_back({"bust_left", {ref->leftPx - shareLeft * half, row}});
  c.out.landmarks.push_back({"bust_right", {ref->rightPx + shareRight * half, row}});
  if (!c.depth)
    return ref->circCm * (1.0 + 0.5 * (shareLeft + shareRight));
  return c.depth->circWithFins(shareLeft, shareRight, ref->circCm);
}

// A garment is worn over the form, so it cannot measure much less round than the form under it
// (a knit stretches by 10 % or so): a smaller reading means the silhouette lost part of the
// garment there (a patch the colour of the form cut out of it, say). It is dropped with a
// warning rather than reported.
constexpr double kMinFractionOfForm = 0.85;

// The depth rule for a circumference `name` of a garment of `type` read at heightCm.
std::optional<DepthModel> depthModelFor(const Context& c, double heightCm, const std::string& name,
                                        const std::string& type) {
  const auto table = depthTable(c.view);
  DepthModel m;
  m.form = sectionOf(*table, std::max(heightCm, c.view.hipCm()));
  if (m.form.widthCm <= 0 || m.form.depthCm <= 0)
    return std::nullopt;
  const bool upper = type == "top" || type == "dress";
  if (name == "bust_circ") {
    m.rule = DepthRule::kBust;
    m.hang = envelopeOf(*table, heightCm, c.view.armpitCm());
  } else if (upper && name == "waist_circ" && c.sleevelessShare > 0) {
    m.rule = DepthRule::kSidesShowShare;
    m.sidesShare = c.sleevelessShare;
  } else if (upper && (name == "waist_circ" || (type == "top" && name == "hem_circ"))) {
    // A top hangs from the bust down to its hem; a dress's bodice down to its waist seam.
    m.rule = DepthRule::kBodice;
    m.hang = envelopeOf(*table, std::max(heightCm, table->firstCm), c.view.armpitCm());
  } else if (name == "hem_circ") {
    m.rule = DepthRule::kHem;
    if (type == "dress") {
      const SectionShape hangs = envelopeOf(*table, c.view.hipCm(), c.view.bustCm());
      m.hemHangCm = kDressHemHangShare * std::max(0.0, hangs.depthCm - m.form.depthCm);
    }
  } else if (name == "hip_circ") {
    m.rule = DepthRule::kEase;
  } else {
    m.rule = DepthRule::kSimilar;  // a skirt's or pants' waistband
  }
  return m;
}

// ---- A loose top's hem (docs/measurement_model.md, "A loose top's hem") ----
// A stiff loose top (a woven with a few cm of ease) stands off the form's sides under the bust,
// where a knit lies on them (physical rigs, 4-8 cm below the bust: knits 0.8-1.7 cm a side,
// wovens 2.6-3.7; h/loose15). Over the hip its sides come back onto the form (the hip is the
// section's widest point, and the cloth rests on it), so its hem is as wide as a knit's there,
// but its front and back keep hanging from what stands out above: the bust in front, the
// shoulder blades and the seat behind. Its hem section is then at least as deep as the envelope
// of the form's sections from the hem up to the armpit, plus the stand-off it hangs with.
constexpr double kLooseStandOffCm = 2.2;       // h/loose15's mark, midway between knits and wovens
constexpr double kLooseUnderBustFromCm = 4.0;  // band under the bust, cm below it
constexpr double kLooseUnderBustToCm = 8.0;

// Median over the clear rows between heights loCm and hiCm of the sides' mean stand-off beyond
// the form's torso edges, cm; nullopt with fewer than 3 such rows.
std::optional<double> sideStandOffCm(Context& c, double loCm, double hiCm) {
  const DepthModel* keep = c.depth;
  c.depth = nullptr;
  std::vector<double> offs;
  const int r0 = static_cast<int>(std::lround(c.view.rowOfHeight(hiCm)));
  const int r1 = static_cast<int>(std::lround(c.view.rowOfHeight(loCm)));
  for (int row = r0; row <= r1; ++row) {
    bool hidden = false;
    const auto v = readRow(c, row, hidden);
    if (!v || hidden || !v->torso || v->torso->widthPx() <= 1)
      continue;
    offs.push_back(0.5 * ((v->torso->leftPx - v->left.x) + (v->right.x - v->torso->rightPx)) / c.s);
  }
  c.depth = keep;
  if (offs.size() < 3)
    return std::nullopt;
  return median(offs);
}

// For a top's hem: when the top stands off the form under the bust (a loose top), its hem's depth
// is at least the envelope's from the hem up plus that stand-off.
void loosenHemDepth(Context& c, DepthModel& model) {
  const double bust = c.view.bustCm();
  const auto under = sideStandOffCm(c, bust - kLooseUnderBustToCm, bust - kLooseUnderBustFromCm);
  if (!under || *under < kLooseStandOffCm || model.hang.depthCm <= 0)
    return;
  // Only over the hip: where the form's section at the hem is wider than the bust's envelope by
  // at least the stand-off (the hip takes up half of what the top stood off at its two sides),
  // the sides rest on the form and what stood off at them hangs at the front and back. Higher, a
  // hem hangs free all round and keeps its sides' stand-off (the eased section). Physical rigs'
  // and a fresh one's woven tops pass this by 0.9-1.4 cm; the simulator's loose tops, whose hems
  // keep the eased section, fail it by 1.8 cm or more (without the stand-off one passed by 0.3 cm
  // and read its hem 0.9 cm large, another failed by 0.5).
  const auto table = depthTable(c.view);
  const SectionShape bustEnvelope = envelopeOf(*table, bust, c.view.armpitCm());
  if (model.form.widthCm < bustEnvelope.widthCm + *under)
    return;
  model.minDepthCm = model.hang.depthCm + *under;
}

std::optional<double> circumferenceAt(Context& c, double heightCm, const std::string& name) {
  auto model = depthModelFor(c, heightCm, name, c.type);
  if (model && c.type == "top" && name == "hem_circ")
    loosenHemDepth(c, *model);
  c.depth = model ? &*model : nullptr;
  const auto value = name == "bust_circ" ? bustFromSides(c, heightCm, name)
                                         : circumferenceReading(c, heightCm, name);
  c.depth = nullptr;
  const auto ref = referenceAt(c.view, heightCm);
  if (value && ref && *value < kMinFractionOfForm * ref->circCm) {
    c.out.warnings.push_back(
        name + ": the silhouette reads " + std::to_string(static_cast<int>(std::lround(*value))) +
        " cm round where the form is " +
        std::to_string(static_cast<int>(std::lround(ref->circCm))) +
        " cm, so part of the garment is missing from it there; not measured, review by hand");
    return std::nullopt;
  }
  return value;
}

// Lowest garment row below `fromRow` along column `col` (following the run down).
std::optional<int> lowestRow(const cv::Mat& mask, int col, int fromRow) {
  if (!maskCovers(mask, fromRow, col))
    return std::nullopt;
  int row = fromRow;
  int gap = 0;
  for (int r = fromRow + 1; r < mask.rows; ++r) {
    if (maskCovers(mask, r, col)) {
      row = r;
      gap = 0;
    } else if (++gap > kMaxGapPx) {
      break;
    }
  }
  return row;
}

struct SleeveEnd {
  double lengthCm = 0;
  cv::Point2d endPx;
};

// Smaller angle (0..pi/2) between two undirected lines with directions a and b.
double lineAngle(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return std::acos(std::min(1.0, std::abs(a.dot(b)) / (a.norm() * b.norm())));
}

// Whether the garment's cover of the arm ends in a bodice's armhole rather than in a sleeve's
// hem (docs/measurement_model.md, "Sleeve or armhole"). A sleeve is a tube round the arm: its hem
// runs across the arm. A sleeveless bodice's armhole runs from the shoulder down to the
// underarm, and so does the edge of an extended shoulder that hangs from beyond the shoulder tip
// (a boxy top on a form with broad shoulder caps covers several cm of the arm's root that way).
// The edge is located where the cover ends along lines parallel to the arm's axis, from its
// centre line to three quarters of the way to its outer edge (the inner half lies on the bodice
// near the shoulder), and compared, as a direction in the arm's frame, with the two: across the
// arm, or along the line from the shoulder tip to the underarm. Cover of the arm's outer edge
// down to the underarm's row is a sleeve whatever its hem looks like: a bodice's armhole has
// reached the body above that row.
bool endsInArmhole(const Context& c, const calib::ArmAxis& arm, double outerSign,
                   const Eigen::Vector2d& normal, double lastCoveredPx) {
  if (!arm.underarmPx)
    return false;
  const double step = std::max(1.0, 0.25 * c.s);
  auto outerEdge = [&](double t) {
    return Eigen::Vector2d(arm.originPx + arm.dir * t +
                           normal * (arm.centreAt(t) + outerSign * arm.halfWidthAt(t)));
  };
  for (double t = 0; t <= lastCoveredPx; t += step)
    if (outerEdge(t).y() >= arm.underarmPx->y())
      return false;
  // (d, t) in cm of the cover's end on each line; d outward from the arm's centre.
  std::vector<Eigen::Vector2d> ends;
  const double tMax = arm.tWristPx + 10.0 * c.s;
  for (const double f : {0.0, 0.25, 0.5, 0.75}) {
    double last = -1;
    for (double t = 0, gap = 0; t <= tMax && gap <= c.s; t += step) {
      const Eigen::Vector2d p = arm.originPx + arm.dir * t +
                                normal * (arm.centreAt(t) + outerSign * f * arm.halfWidthAt(t));
      if (maskCovers(c.mask, static_cast<int>(std::lround(p.y())),
                     static_cast<int>(std::lround(p.x())))) {
        last = t;
        gap = 0;
      } else {
        gap += step;
      }
    }
    if (last >= 0)
      ends.emplace_back(f * arm.halfWidthAt(last) / c.s, last / c.s);
  }
  if (ends.size() < 3)
    return false;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& e : ends)
    mean += e;
  mean /= static_cast<double>(ends.size());
  double sdd = 0, sdt = 0;
  for (const auto& e : ends) {
    sdd += (e.x() - mean.x()) * (e.x() - mean.x());
    sdt += (e.x() - mean.x()) * (e.y() - mean.y());
  }
  if (sdd <= 0)
    return false;
  // Directions as (d, t) in the arm's frame: the fitted edge, a hem across the arm, and the
  // armhole line from the shoulder tip to the underarm.
  const Eigen::Vector2d edge(1.0, sdt / sdd);
  const Eigen::Vector2d hem(1.0, 0.0);
  auto frame = [&](const Eigen::Vector2d& p) {
    const double t = arm.t(p);
    return Eigen::Vector2d(outerSign * (arm.d(p) - arm.centreAt(t)), t);
  };
  const Eigen::Vector2d armhole = frame(*arm.underarmPx) - frame(arm.shoulderTipPx);
  if (armhole.norm() <= 0)
    return false;
  return lineAngle(edge, armhole) < lineAngle(edge, hem);
}

// Sleeve length on one arm: along the arm axis from the shoulder tip, as far as the garment
// covers the outer half of the arm (the side away from the body, which a bodice never reaches).
std::optional<SleeveEnd> sleeveOnArm(Context& c, int side) {
  const auto& arm = c.view.arm(side);
  if (!arm)
    return std::nullopt;
  // Sign of d on the arm's outer side.
  const Eigen::Vector2d away(side == 0 ? -1.0 : 1.0, 0.0);
  const double outerSign =
      arm->d(arm->originPx + away * 10.0) - arm->d(arm->originPx) > 0 ? 1.0 : -1.0;
  const double step = std::max(1.0, 0.5 * c.s);  // bins of 0.5 cm along the arm
  const double tMax = arm->tWristPx + 10.0 * c.s;
  const Eigen::Vector2d normal(arm->dir.y(), -arm->dir.x());  // direction of increasing d
  double lastCovered = -1;
  int misses = 0;
  for (double t = 0.5 * c.s; t <= tMax; t += step) {
    const double hw = arm->halfWidthAt(t);
    if (hw < 1)
      break;
    int set = 0, total = 0;
    for (double f = 0.25; f <= 0.85; f += 0.1) {
      const double d = arm->centreAt(t) + outerSign * f * hw;
      const Eigen::Vector2d p = arm->originPx + arm->dir * t + normal * d;
      const int x = static_cast<int>(std::lround(p.x())), y = static_cast<int>(std::lround(p.y()));
      if (x < 0 || y < 0 || x >= c.mask.cols || y >= c.mask.rows)
        continue;
      ++total;
      set += maskCovers(c.mask, y, x) ? 1 : 0;
    }
    if (total > 0 && set * 2 > total) {
      lastCovered = t;
      misses = 0;
    } else if (lastCovered < 0 && t > 3.0 * c.s) {
      return SleeveEnd{0.0, {}};  // nothing on the arm near the shoulder: sleeveless
    } else if (lastCovered >= 0 && lastCovered < 5.0 * c.s && t > 6.0 * c.s) {
      return SleeveEnd{0.0, {}};  // only the shoulder's edge: sleeveless
    } else if (lastCovered >= 0 && ++misses >= 3) {
      break;
    }
  }
  // The bodice's shoulder covers the arm's root for a few cm; a sleeve (8 cm and more) goes on.
  if (lastCovered < 5.0 * c.s)
    return SleeveEnd{0.0, {}};
  if (endsInArmhole(c, *arm, outerSign, normal, lastCovered))
    return SleeveEnd{0.0, {}};
  // Refine the end: the farthest garment pixel along the axis within the arm's tube near the
  // coarse end.
  double tEnd = lastCovered;
  for (double t = lastCovered; t <= lastCovered + 2 * step; t += 0.5) {
    const double hw = arm->halfWidthAt(t);
    bool any = false;
    for (double f = -0.8; f <= 0.8; f += 0.2) {
      const Eigen::Vector2d p = arm->originPx + arm->dir * t + normal * (arm->centreAt(t) + f * hw);
      if (maskCovers(c.mask, static_cast<int>(std::lround(p.y())),
                     static_cast<int>(std::lround(p.x()))))
        any = true;
    }
    if (any)
      tEnd = t;
  }
  const Eigen::Vector2d e = arm->originPx + arm->dir * tEnd;
  return SleeveEnd{(tEnd + 0.5) / c.s, {e.x(), e.y()}};
}

// The garment's top in column `col` (beside the neck, see garment_length): the first covered row
// below `fromRow` whose cover goes on down to the form's shoulder line in that column (gaps up to
// kTopGapCm bridged); below the shoulder line any cover is the garment's. A neckline, or a collar
// above it, lies on the shoulder and goes on down over it; a patch of the head or neck the column
// grazes does not reach it (a dark dress throws less light back on the chin and the neck's side
// than the bare form had, so they differ from the bare frame and join the silhouette: a physical
// rig's garment length read 12 cm long from the jaw's edge).
std::optional<int> garmentTopRow(const Context& c, int col, int fromRow, int toRow) {
  const auto& outline = c.view.topOutline();
  const int shoulder = col >= 0 && col < static_cast<int>(outline.size())
                           ? outline[static_cast<std::size_t>(col)]
                           : -1;
  const int maxGap = std::max(kMaxGapPx, static_cast<int>(std::lround(kTopGapCm * c.s)));
  for (int r = fromRow; r < toRow; ++r) {
    if (!maskCovers(c.mask, r, col))
      continue;
    if (shoulder < 0 || r >= shoulder)
      return r;
    int last = r, gap = 0;
    for (int k = r + 1; k < toRow && k <= shoulder && gap <= maxGap; ++k) {
      if (maskCovers(c.mask, k, col)) {
        last = k;
        gap = 0;
      } else {
        ++gap;
      }
    }
    if (last + maxGap >= shoulder)
      return r;
    r = last;  // a piece that does not reach the shoulder: look below it
  }
  return std::nullopt;
}

// The height of a point seen at image row `row` that lies at depth `zCm` (form coordinates, +z
// towards the camera) rather than on the form's axis plane, where heightOfRow reads it. In
// perspective a camera below a point sees it lower the further behind the axis it lies, and a
// camera above it sees it lower the further in front: at 3 m, 4 cm of depth 50 cm above or below
// the lens moves a height by 0.7 cm. Orthographic views read the row as it is.
double heightAtDepthCm(const Context& c, double row, double zCm) {
  const double onAxis = c.view.heightOfRow(row);
  const calib::FormPose& pose = c.view.pose();
  if (!pose.perspective)
    return onAxis;
  const calib::Intrinsics& k = *pose.perspective;
  return onAxis + (k.cy - row) * (c.view.form().axisZCm() - zCm) / k.fy;
}

// The height of a hem whose centre front is seen at image row `hemRow`: the silhouette's lowest
// point at the centre is the hem's front, and its depth is taken from the form's hip section.
// A skirt's centre front (a dress's skirt's too) falls straight from the hip's front: it is cut
// on the straight grain, and an A-line's flare, added at the side seams, shows in a front view
// as width. So a skirt's or dress's hem front lies at the depth of the hip's front whatever the
// hem's width: on the physical rigs' settled cloth (seeds 2026 and 2015, full and torso form,
// their 23 skirts and dresses) it lies 8.1-12.0 cm in front of the axis where the hip's front
// is 9.9 cm, while the hip section scaled to the hem's width put the A-lines' at 12.9-15.9 cm
// and their hems read 0.5-1.1 cm high for it. A top's hem hangs from the bust, a knit's close
// to the form and a woven's further out (10.1-17.9 cm on the same rigs): it keeps the hip section
// scaled to the garment's widest run in the kHemWidthBandCm above the hem.
double frontHemHeightCm(const Context& c, double hemRow, int axisCol) {
  const calib::FormSection hip = c.view.form().section(c.view.hipCm());
  double minZ = 0, maxZ = 0;
  bool any = false;
  for (const auto& loop : hip.torsoLoops)
    for (const auto& p : loop) {
      minZ = any ? std::min(minZ, p.y()) : p.y();
      maxZ = any ? std::max(maxZ, p.y()) : p.y();
      any = true;
    }
  if (!any)
    return c.view.heightOfRow(hemRow);
  if (c.type != "top")
    return heightAtDepthCm(c, hemRow, maxZ);
  const auto hipRow = c.view.torsoAtHeight(c.view.hipCm());
  double widest = 0;
  const int band = static_cast<int>(std::lround(kHemWidthBandCm * c.s));
  for (int r = static_cast<int>(hemRow) - band; r < static_cast<int>(hemRow); ++r)
    if (const auto run = runAt(c.mask, r, axisCol))
      widest = std::max(widest, run->second - run->first);
  if (!hipRow || hipRow->widthPx() <= 1 || widest <= 0)
    return c.view.heightOfRow(hemRow);
  const double centreZ = 0.5 * (minZ + maxZ);
  return heightAtDepthCm(c, hemRow, centreZ + (maxZ - centreZ) * widest / hipRow->widthPx());
}

// How a hem that is not level shows in a front view. Its full width ends at the last row whose
// run is at least kHemFullShare of the widest in the kHemWidthBandCm-high band from
// kHemLevelSearchCm above the centre's lowest edge (below the form's waist; a hem less than
// kHemLevelMinCm below the waist is not judged). Below that row the garment still covers at
// least kHemCoverShare of that width down to `dropCm` lower (or the centre's lowest edge lies
// that much lower, whichever is lower), and what covers it there lies
// `shiftCm` (its mean column; image +x) off the centre line. A level hem's edge runs straight
// across but for its corners and the perspective of its front: 41 level skirts and dresses and
// 31 tops of five physical rigs drop at most 2.6 cm; a leg's shade under a skirt's hem, which can
// join the silhouette, covers less than kHemCoverShare. A high-low hem's back hangs below its
// front, lowest at the centre; an asymmetric hem slants from one side down to the other, so what
// lies below the full width lies to one side.
struct HemLevel {
  double dropCm = 0;
  double shiftCm = 0;
  double widthCm = 0;
  double fullEdge = 0;  // the lower edge of the last row the full width covers
};

HemLevel hemLevel(const Context& c, double hemEdge, int axisCol) {
  const int hem = static_cast<int>(hemEdge) - 1;  // the centre's last covered row
  // Not above the form's waist: a cropped top's search would reach its sleeves.
  const int from =
      std::max(hem - static_cast<int>(std::lround((kHemLevelSearchCm + kHemWidthBandCm) * c.s)),
               static_cast<int>(std::lround(c.view.rowOfHeight(c.view.waistCm()))));
  if (hem - from < static_cast<int>(std::lround(kHemLevelMinCm * c.s)))
    return {};  // too little below the waist to tell
  const int bandEnd = hem - static_cast<int>(std::lround(kHemWidthBandCm * c.s));
  double widest = 0;
  for (int r = from; r < bandEnd; ++r)
    if (const auto run = runAt(c.mask, r, axisCol))
      widest = std::max(widest, run->second - run->first);
  if (widest <= 0)
    return {};
  std::optional<int> full;
  std::pair<double, double> span;
  for (int r = from; r <= hem; ++r)
    if (const auto run = runAt(c.mask, r, axisCol);
        run && run->second - run->first >= kHemFullShare * widest) {
      full = r;
      span = *run;
    }
  if (!full)
    return {};
  const int left = std::max(0, static_cast<int>(std::floor(span.first)));
  const int right = std::min(c.mask.cols - 1, static_cast<int>(std::ceil(span.second)));
  int low = *full;
  double sumX = 0;
  long count = 0;
  for (int r = *full + 1; r < c.mask.rows; ++r) {
    int covered = 0;
    double rowX = 0;
    for (int x = left; x <= right; ++x)
      if (maskCovers(c.mask, r, x)) {
        ++covered;
        rowX += x;
      }
    if (covered < kHemCoverShare * (right - left + 1))
      break;
    low = r;
    sumX += rowX;
    count += covered;
  }
  HemLevel out;
  out.widthCm = (span.second - span.first) / c.s;
  out.fullEdge = *full + 1.0;
  // Or the centre's own lowest edge, when what hangs below there is narrower than
  // kHemCoverShare of the width (a curved hem's tail; no case of the rigs needed it).
  out.dropCm = (std::max(low, hem) - *full) / c.s;
  if (count > 0)
    out.shiftCm = (sumX / static_cast<double>(count) - axisCol) / c.s;
  return out;
}

// The depth (form z) of the form's shoulder ridge under image column `col`: the mean depth of the
// form's highest surface in a 1 cm wide slab there, below the side neck plus kRidgeHeadCm (the
// head and jaw stand above it). A garment's top beside the neck lies on this ridge, 2-7 cm behind
// the axis plane on the bundled form (physical rig, seed 2026: its fourteen tops' and dresses'
// highest cloth lies 1.9-7.2 cm behind the axis).
std::optional<double> shoulderRidgeZ(const Context& c, int col) {
  const calib::FormModel& form = c.view.form();
  const double xCm = form.axisXCm() + (col - c.view.axisXPx()) / c.s;
  const double ceiling = c.view.neckSideCm() + kRidgeHeadCm;
  std::optional<double> top;
  for (const auto& v : form.mesh().vertices)
    if (std::abs(v.x() - xCm) < 0.5 && v.y() < ceiling)
      top = std::max(top.value_or(v.y()), v.y());
  if (!top)
    return std::nullopt;
  double sum = 0;
  int n = 0;
  for (const auto& v : form.mesh().vertices)
    if (std::abs(v.x() - xCm) < 0.5 && v.y() < ceiling && v.y() > *top - kRidgeBandCm) {
      sum += v.z();
      ++n;
    }
  return sum / n;
}

// The lowest row of one pants leg, going down from `fromRow` along the form's leg: the run
// across the leg (on its side of the axis) must stay at least kHemTailShare of its widest in the
// kHemTailCm above. The garment's shadow on the shin below the hem joins the silhouette as a
// narrow tail (a physical rig's leg openings read 7-13 cm small, measured across the tail).
std::optional<int> legHemRow(const Context& c, int side, int fromRow, int axisCol) {
  const int window = std::max(2, static_cast<int>(std::lround(kHemTailCm * c.s)));
  std::vector<double> widths;
  std::optional<int> last;
  for (int r = fromRow; r < c.mask.rows; ++r) {
    const auto leg = c.view.legAtRow(r, side);
    if (!leg)
      break;
    const auto run = runAt(c.mask, r, static_cast<int>(std::lround(leg->centrePx())),
                           side == 0 ? -1 : axisCol, side == 0 ? axisCol : -1);
    if (!run)
      break;
    const double w = run->second - run->first;
    const std::size_t from =
        widths.size() > static_cast<std::size_t>(window) ? widths.size() - window : 0;
    const double widest =
        widths.empty() ? w
                       : *std::max_element(widths.begin() + static_cast<long>(from), widths.end());
    if (w < kHemTailShare * widest)
      break;
    widths.push_back(w);
    last = r;
  }
  return last;
}

// One leg's section of the form (side 0: the image's left leg, the form's x below its axis): the
// x and z extent and the convex-hull perimeter of the largest loop on that side of `sec`.
struct LegSlice {
  double minX = 0, maxX = 0, minZ = 0, maxZ = 0, perimeter = 0;
};
std::optional<LegSlice> formLegSlice(const calib::FormSection& sec, double axisXCm, int side) {
  const calib::SliceLoop* best = nullptr;
  for (const auto& loop : sec.torsoLoops) {
    if (loop.size() < 3)
      continue;
    double cx = 0;
    for (const auto& p : loop)
      cx += p.x();
    cx = cx / static_cast<double>(loop.size()) - axisXCm;
    if ((side == 0 ? cx < 0 : cx > 0) && (!best || loop.size() > best->size()))
      best = &loop;
  }
  if (!best)
    return std::nullopt;
  std::vector<cv::Point2f> pts;
  pts.reserve(best->size());
  LegSlice out{best->front().x(), best->front().x(), best->front().y(), best->front().y(), 0};
  for (const auto& p : *best) {
    pts.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
    out.minX = std::min(out.minX, p.x());
    out.maxX = std::max(out.maxX, p.x());
    out.minZ = std::min(out.minZ, p.y());
    out.maxZ = std::max(out.maxZ, p.y());
  }
  std::vector<cv::Point2f> hull;
  cv::convexHull(pts, hull);
  out.perimeter = cv::arcLength(hull, true);
  return out;
}

// Sampling step and neighbourhood of the form's leg profile for the knee (legSideViewDepthCm).
constexpr double kKneeStepCm = 0.5;
constexpr double kKneeWindowCm = 2.0;

// Both legs of a form sliced every kKneeStepCm from the floor to the top of the leg (5 cm under
// the crotch), once per form: slicing the mesh per capture cost a pants capture 20-80 ms.
struct LegTable {
  double firstCm = 0;  // height of sample 0
  std::array<std::vector<std::optional<LegSlice>>, 2> legs;
};

std::shared_ptr<const LegTable> legTable(const FormView& view) {
  const calib::FormModel& form = view.form();
  // Keyed by what identifies a loaded form, by value (as depthTable's cache, for its reasons).
  struct Key {
    std::size_t vertices, triangles;
    double minY, maxY, axisX, axisZ, crotch, sample;
    bool operator==(const Key&) const = default;
  };
  const auto& vs = form.mesh().vertices;
  double sample = 0;
  for (std::size_t i = 0; i < vs.size(); i += std::max<std::size_t>(1, vs.size() / 64))
    sample += vs[i].x() + 3.0 * vs[i].y() + 7.0 * vs[i].z();
  const Key key{vs.size(),      form.mesh().faces.size(), form.minYCm(),    form.maxYCm(),
                form.axisXCm(), form.axisZCm(),           *view.crotchCm(), sample};
  static std::mutex mutex;
  static std::vector<std::pair<Key, std::shared_ptr<const LegTable>>> cache;
  {
    const std::lock_guard lock(mutex);
    for (const auto& [k, t] : cache)
      if (k == key)
        return t;
  }
  auto table = std::make_shared<LegTable>();
  table->firstCm = form.minYCm() + kKneeStepCm;
  for (double h = table->firstCm; h <= *view.crotchCm() - 5.0 + 1e-9; h += kKneeStepCm) {
    const calib::FormSection sec = form.section(h);
    for (int side = 0; side < 2; ++side)
      table->legs[side].push_back(formLegSlice(sec, form.axisXCm(), side));
  }
  const std::lock_guard lock(mutex);
  if (cache.size() >= 8)
    cache.erase(cache.begin());
  cache.emplace_back(key, table);
  return table;
}

// Depth (front to back, cm) of the form's leg on `side` seen from the side between `fromCm`
// and the knee: the z extent of the leg's sections over that span. A trouser leg below the knee
// hangs straight down from what it rests on, the kneecap in front and the calf behind, so its
// opening is at least that deep (a physical rig's slim and straight legs: 12.4-15.3 cm deep
// where the ankle under them is 7.5-10 cm deep; docs/measurement_model.md, "Leg openings that
// hang from the knee"). The knee is the narrowest section (convex-hull perimeter) that the leg
// reaches going up from `fromCm`: the first one no larger than any within kKneeWindowCm of it,
// below which the leg was larger. nullopt when the leg has no such narrowing below the top of
// the leg (5 cm under the crotch): then there is no knee below the thigh to hang from.
std::optional<double> legSideViewDepthCm(const FormView& view, int side, double fromCm) {
  if (!view.crotchCm())
    return std::nullopt;
  const auto table = legTable(view);
  const auto& leg = table->legs[side];
  const int k = static_cast<int>(std::lround(kKneeWindowCm / kKneeStepCm));
  const auto first = static_cast<long>(std::ceil((fromCm - table->firstCm) / kKneeStepCm - 1e-9));
  if (first < 0)
    return std::nullopt;
  const auto n = static_cast<long>(leg.size());
  for (long i = first + k; i + k < n; ++i) {
    bool lowest = true;
    for (long j = i - k; j <= i + k && lowest; ++j)
      lowest = leg[j] && leg[i] && leg[i]->perimeter <= leg[j]->perimeter;
    if (!lowest || !(leg[i]->perimeter < leg[i - k]->perimeter))
      continue;
    double minZ = leg[i]->minZ, maxZ = leg[i]->maxZ;
    for (long j = first; j <= i; ++j) {
      if (!leg[j])
        return std::nullopt;
      minZ = std::min(minZ, leg[j]->minZ);
      maxZ = std::max(maxZ, leg[j]->maxZ);
    }
    return maxZ - minZ;
  }
  return std::nullopt;
}

// The round of one pants leg's opening from its run across the row it is read on (side 0 is
// the image's left leg, its run limited at the axis column; `here` the form's leg at that row).
// - a free leg (a gap of kPressedLegGapCm or more to the centre line) hangs round the form's
//   leg: that leg's section scaled to the leg's width, the width being the larger of its run and
//   twice the leg's centre to its outer edge (the inner edge can be pulled in, on a form whose
//   legs nearly touch; the outer edge hangs free);
// - a leg pressed against the other one (its inner edge within kPressedLegGapCm of the centre
//   line: wide legs, which stand far off the lower leg) is a tube hanging from the top of the
//   leg whose inner side is flattened by its twin. Pressing does not shorten the cloth: the
//   opening keeps the round it would have hanging free, a circle about the point it hangs from
//   through its outer edge, which nothing touches; what the circle has beyond the centre line
//   goes to the front and back (the physical rig's touching wide legs are 1.3 times as deep as
//   wide). The tube hangs from the thigh and round the leg inside it, so its centre lies between
//   the form's leg centre at the top of the leg (5 cm below the crotch) and at the reading row;
//   the one nearer the centre line gives the larger radius and is taken (the physical rig's
//   form: the thigh's; a form whose legs close in downward: the ankle's). Scaling the ankle's
//   section instead read the physical rig's pressed wide legs 6.7 cm small and 2.8 cm large.
std::optional<double> legOpeningCm(const Context& c, int side, const std::pair<double, double>& run,
                                   int axisCol, double topCentrePx, const RowSection& here) {
  const double centreLine = axisCol + 0.5;
  const double inner = side == 0 ? run.second : run.first;
  const double outer = side == 0 ? run.first : run.second;
  const bool reachesCentre = side == 0 ? inner >= centreLine : inner <= centreLine;
  if (reachesCentre || std::abs(centreLine - inner) < kPressedLegGapCm * c.s) {
    const double radiusPx = side == 0 ? std::max(topCentrePx, here.centrePx()) - outer
                                      : outer - std::min(topCentrePx, here.centrePx());
    if (radiusPx <= 0)
      return std::nullopt;
    return 2.0 * std::numbers::pi * radiusPx / c.s;
  }
  if (here.widthPx() <= 1)
    return std::nullopt;
  const double outerHalfPx = std::abs(outer - here.centrePx());
  const double widthPx = std::max(run.second - run.first, 2.0 * outerHalfPx);
  // The form's leg section scaled to the leg's width, with two bounds on its depth:
  // - a leg at least as wide as the form's leg there is deep hangs free of it (a round tube as
  //   wide clears it front and back), and nothing holds a free cloth tube deeper than it is wide:
  //   the ankle's section scaled (1.2-1.4 times as deep as wide) is capped at the width. A
  //   narrower one lies on the leg and keeps its shape (docs/measurement_model.md, "A free leg
  //   is no deeper than wide, in the simulator as in the measurer");
  // - a leg hanging from the knee is never shallower than the leg's side view below the knee
  //   (legSideViewDepthCm).
  // Where either moves the depth, the opening is an ellipse as wide as the leg and that deep.
  const auto at = formLegSlice(c.view.form().section(here.heightCm), c.view.form().axisXCm(), side);
  const auto hangDepth = legSideViewDepthCm(c.view, side, here.heightCm);
  if (at && hangDepth && at->maxX > at->minX) {
    const double widthCm = widthPx * (at->maxX - at->minX) / here.widthPx();
    const double legDepthCm = at->maxZ - at->minZ;
    const double scaledDepthCm = legDepthCm * widthPx / here.widthPx();
    double depthCm = widthCm >= legDepthCm ? std::min(scaledDepthCm, kFreeLegDepthShare * widthCm)
                                           : scaledDepthCm;
    depthCm = std::max(depthCm, *hangDepth);
    if (depthCm != scaledDepthCm)
      return ellipsePerimeter(widthCm, depthCm);
  }
  return here.circCm * widthPx / here.widthPx();
}

// Distance in px between the garment's outermost pixels within `reach` of the axis at `row`;
// nullopt when the row holds none.
std::optional<double> outerWidthPx(const cv::Mat& mask, int row, int axis, int reach) {
  if (row < 0 || row >= mask.rows)
    return std::nullopt;
  const uchar* m = mask.ptr(row);
  int lo = -1, hi = -1;
  for (int x = std::max(0, axis - reach); x <= std::min(mask.cols - 1, axis + reach); ++x)
    if (m[x]) {
      lo = lo < 0 ? x : lo;
      hi = x;
    }
  if (lo < 0)
    return std::nullopt;
  return static_cast<double>(hi - lo + 1);
}

// Width in px of the gap between the legs at `row`: the run of uncovered pixels around the
// axis column, between the nearest garment pixels on either side; nullopt when the axis is
// covered or a side has no garment within 25 cm.
std::optional<double> gapBetweenLegsPx(const Context& c, int row, int axisCol) {
  if (row < 0 || row >= c.mask.rows || maskCovers(c.mask, row, axisCol))
    return std::nullopt;
  const int reach = static_cast<int>(std::lround(25.0 * c.s));
  int left = -1, right = -1;
  for (int x = axisCol - 1; x >= std::max(0, axisCol - reach) && left < 0; --x)
    if (maskCovers(c.mask, row, x))
      left = x;
  for (int x = axisCol + 1; x <= std::min(c.mask.cols - 1, axisCol + reach) && right < 0; ++x)
    if (maskCovers(c.mask, row, x))
      right = x;
  if (left < 0 || right < 0)
    return std::nullopt;
  return static_cast<double>(right - left - 1);
}

// The crotch height from the first row where the legs part (`partRow`). Pants legs whose inner
// edges touch below the crotch part only lower down (6.5-8.5 cm below the form's crotch on a
// physical rig, inseams 4-6 cm short): when the parting starts more than kTouchingLegsCm below
// the form's crotch, the gap's V over the next kGapFitCm is fitted (width against row) and
// followed up to where it closes, but never above the form's crotch. The simulator's pants part
// where their crotch is, 3.9 cm below the bundled form's: there the V, followed up, read the
// crotch 1.2 cm high, so the parting row stands.
double crotchHeightCm(const Context& c, int partRow, int axisCol) {
  const double partH = c.view.heightOfRow(partRow);
  const auto formCrotch = c.view.crotchCm();
  if (!formCrotch || *formCrotch - partH <= kTouchingLegsCm)
    return partH;
  const int rows = static_cast<int>(std::lround(kGapFitCm * c.s));
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (int k = 0; k <= rows; ++k) {
    const auto w = gapBetweenLegsPx(c, partRow + k, axisCol);
    if (!w)
      break;  // the gap must be one piece below the parting
    sx += k;
    sy += *w;
    sxx += static_cast<double>(k) * k;
    sxy += k * *w;
    ++n;
  }
  if (n < rows / 2)
    return partH;
  const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  const double at0 = (sy - slope * sx) / n;
  if (!(slope > 0.05))
    return partH;  // no V: a gap of parallel edges says nothing about where it closes
  const double apexRow = partRow - at0 / slope;
  c.out.warnings.push_back(
      "inseam: the legs touch below the crotch; the crotch is where the gap between them, "
      "followed up, closes");
  return std::min(*formCrotch, c.view.heightOfRow(apexRow));
}

}  // namespace

std::optional<double> measurementUncertaintyCm(const std::string& name) {
  // `garmcap rig eval` (registered from the bare frame) on nine rigs of cloth draped by the
  // independent solver, pooled: the five committed ones (tests/data/rig_physical, 24 cases on the
  // full form; rig_physical_torso, 16 on the torso form; rig_physical_pants, 10 pants;
  // rig_physical_shade and rig_physical_hem_shade) and four fresh ones made with the documented
  // commands and kept outside the repo (seeds 8686, 24 cases; 4242, 8 tops; 7373, 5; 5252, 10 on
  // the torso form). Per measurement the nearest-rank 96th percentile of |error| over the
  // correctly typed cases' readings (n in brackets); with fewer than 40 readings the largest error
  // seen. Rounded up to 0.1 cm. The level and the 40 are what makes the claim hold on a rig the
  // table was not made from: each rig scored against the table made from the other eight holds
  // 485 of 507 readings within it (95.7 %; docs/measurement_model.md, "Uncertainty"), where the
  // plain 95th percentile, the largest below 20 readings, held 473 (93.3 %): the rigs differ
  // more from one another than their readings do within one. The large values are the rigs'
  // known failures: the hem of a loose bodice hanging as deep as wide and of a light top whose
  // shade reads as form, sleeveless bodices' waists whose depth a front view does not show, wide
  // legs pressed together (leg opening: pants case_006, 20.0 cm small), a checked straight leg
  // whose crotch is read low (inseam: pants case_032, 6.3 short), two tops' lengths (the torso
  // rig's light woven case_000, 2.3 long; seed 4242's case_015, 2.3 short).
  static const std::map<std::string, double> kU95 = {
      {"bust_circ", 2.3},          // (56)
      {"waist_circ", 4.5},         // (100)
      {"hip_circ", 3.0},           // (67)
      {"hem_circ", 8.0},           // (75)
      {"garment_length", 2.4},     // (57)
      {"skirt_length", 0.7},       // (41)
      {"sleeve_length", 1.6},      // (39)
      {"outseam", 2.6},            // (24)
      {"inseam", 6.3},             // (24)
      {"leg_opening_circ", 20.1},  // (24)
  };
  const auto it = kU95.find(name);
  if (it == kU95.end())
    return std::nullopt;
  return it->second;
}

GarmentMeasurement measureGarment(const cv::Mat& garmentMask, const FormView& view,
                                  const std::string& type, const cv::Mat& frameBgr) {
  const auto& names = drafts::garmentMeasurementNames(type);
  if (garmentMask.size() != view.size() || garmentMask.type() != CV_8UC1)
    throw std::invalid_argument("measure: the garment mask must be CV_8UC1 of the frame's size");
  if (!frameBgr.empty() && (frameBgr.size() != view.size() || frameBgr.type() != CV_8UC3))
    throw std::invalid_argument("measure: the frame must be CV_8UC3 of the mask's size");
  GarmentMeasurement out;
  Context c{garmentMask, view, view.pose().pxPerCm, out, type};
  auto wants = [&](const std::string& n) {
    return std::find(names.begin(), names.end(), n) != names.end();
  };
  auto put = [&](const std::string& n, std::optional<double> v) {
    if (v && std::isfinite(*v))
      out.measurements[n] = *v;
  };

  // The sleeves first: a sleeveless bodice's waist is read by a rule of its own.
  std::vector<std::optional<SleeveEnd>> sleeves;
  if (wants("sleeve_length")) {
    for (int side = 0; side < 2; ++side)
      sleeves.push_back(sleeveOnArm(c, side));
    double longest = -1;
    for (const auto& s : sleeves)
      if (s)
        longest = std::max(longest, s->lengthCm);
    // longest -1: the form has no arms, and every bodice on it is sleeveless.
    if (longest < 0)
      c.sleevelessShare = kArmlessSideShare;
    else if (longest < kSleevelessBelowCm)
      c.sleevelessShare = kSleevelessSideShare;
  }

  if (wants("bust_circ") && formInFrame(c, view.bustCm(), "bust_circ", "bust"))
    put("bust_circ", circumferenceAt(c, view.bustCm(), "bust_circ"));
  if (wants("waist_circ") && formInFrame(c, view.waistCm(), "waist_circ", "waist"))
    put("waist_circ", circumferenceAt(c, view.waistCm(), "waist_circ"));
  if (wants("hip_circ") && formInFrame(c, view.hipCm(), "hip_circ", "hip"))
    put("hip_circ", circumferenceAt(c, view.hipCm(), "hip_circ"));

  // Top edge and hem at the centre front (the body axis column).
  const int axisCol = static_cast<int>(std::lround(view.axisXPx()));
  const int waistRow = static_cast<int>(std::lround(view.rowOfHeight(view.waistCm())));
  if (type == "pants") {
    // The legs are read from 5 cm below the form's crotch (legAtRow below).
    if (view.crotchCm() &&
        !formInFrame(c, *view.crotchCm() - 5.0, "outseam, inseam, leg_opening_circ",
                     "crotch (and the legs 5 cm below it)"))
      return out;
    const int hipRow = static_cast<int>(std::lround(view.rowOfHeight(view.hipCm())));
    // Crotch: going down the axis from the hip, the first row where the legs part.
    std::optional<int> crotchRow;
    for (int r = hipRow; r < garmentMask.rows; ++r)
      if (!maskCovers(garmentMask, r, axisCol) && !maskCovers(garmentMask, r + 1, axisCol)) {
        crotchRow = r;
        break;
      }
    std::vector<double> hems, openings;
    std::optional<int> lows[2];
    std::optional<double> topCentre[2];  // each leg's centre at the top of the leg, px
    for (int side = 0; side < 2 && crotchRow; ++side) {
      const auto leg = view.legAtRow(*crotchRow + static_cast<int>(5 * c.s), side);
      if (!leg)
        continue;
      topCentre[side] = leg->centrePx();
      lows[side] = legHemRow(c, side, *crotchRow + static_cast<int>(5 * c.s), axisCol);
      if (!lows[side])
        continue;
      hems.push_back(*lows[side] + 1.0);  // bottom edge of the last covered row
      out.landmarks.push_back(
          {side == 0 ? "hem_left" : "hem_right", {leg->centrePx(), *lows[side] + 1.0}});
    }
    // Both openings are read above the higher of the two hems: a pair's legs are cut alike and
    // hang alike, and what makes one leg's hem lower than the other's is the garment's shadow on
    // the shin joining it as a tail that narrows by less than kHemTailShare at first (a physical
    // rig's slim pants: one leg's hem 1.2 cm lower, read across the tail's notch at 53 px
    // against the other leg's 69, the opening 5.7 cm small).
    std::optional<int> highestLow;
    for (const auto& l : lows)
      if (l)
        highestLow = highestLow ? std::min(*highestLow, *l) : *l;
    for (int side = 0; side < 2 && highestLow; ++side) {
      if (!lows[side])
        continue;
      const int row = static_cast<int>(std::lround(*highestLow - kAboveHemCm * c.s));
      const auto legHere = view.legAtRow(row, side);
      const auto run =
          legHere ? runAt(garmentMask, row, static_cast<int>(std::lround(legHere->centrePx())),
                          side == 0 ? -1 : axisCol, side == 0 ? axisCol : -1)
                  : std::nullopt;
      if (legHere && run && topCentre[side])
        if (const auto o = legOpeningCm(c, side, *run, axisCol, *topCentre[side], *legHere))
          openings.push_back(*o);
    }
    if (!crotchRow || hems.empty()) {
      out.warnings.push_back("pants: no crotch or leg hem found in the silhouette");
    } else {
      const double hemH = view.heightOfRow(median(hems));
      out.landmarks.push_back(
          {"crotch", {static_cast<double>(axisCol), static_cast<double>(*crotchRow)}});
      put("outseam", view.waistCm() - hemH);
      put("inseam", crotchHeightCm(c, *crotchRow, axisCol) - hemH);
      if (!openings.empty())
        put("leg_opening_circ", median(openings));
    }
    return out;
  }

  // The hem at the centre front: the median of the lowest covered rows of columns spread over the
  // middle third of the waist, so that a notch or slit the segmentation leaves at the centre
  // (a form-coloured or green patch cut out of the garment) does not lift the hem.
  // A skirt's waistband can sit a little below the form's waist at the centre front (a physical
  // rig's skirt: its band's top edge dipped 1 cm below there), so the hem is followed down from
  // the first covered row within kWaistbandDropCm.
  const int drop = static_cast<int>(std::lround(kWaistbandDropCm * c.s));
  int fromRow = std::min(waistRow, garmentMask.rows - 1);
  while (fromRow < std::min(waistRow + drop, garmentMask.rows - 1) &&
         !maskCovers(garmentMask, fromRow, axisCol))
    ++fromRow;
  if (!maskCovers(garmentMask, fromRow, axisCol)) {
    out.warnings.push_back("the garment does not cover the centre front at the waist");
    return out;
  }
  const auto waistSection = view.torsoAtRow(std::min(waistRow, garmentMask.rows - 1));
  const double spread = waistSection ? waistSection->widthPx() / 6.0 : 0.0;
  std::vector<double> lowest;
  for (int k = -4; k <= 4; ++k) {
    const int col = axisCol + static_cast<int>(std::lround(k * spread / 4.0));
    if (const auto low = lowestRow(garmentMask, col, fromRow))
      lowest.push_back(static_cast<double>(*low));
  }
  const double hemEdge = median(lowest) + 1.0;  // lower edge of the last covered row
  // A high-low hem's back, seen under its front's hem, shows as a dark band (its inside) across
  // the middle down to the outline's lowest edge. Its top is the front's hem edge, where the
  // centre-front lengths and the hem are read (docs/measurement_model.md, "Hems that are not
  // level" and "A high-low hem read at its front": four high-low skirts and dresses on the full
  // form, bands of 8.3-13.4 cm, their lengths then within 0.35 cm; 43 level skirts and dresses of
  // five physical rigs, at most 0.6 cm). A back as dark as its front gives no band.
  std::optional<HemBand> band;
  if (!frameBgr.empty() && (type == "skirt" || type == "dress"))
    band = darkBandAboveHem(frameBgr, garmentMask, {static_cast<double>(axisCol), hemEdge},
                            view.rowOfHeight(view.hipCm()), c.s);
  if (band && band->depthCm <= kHemBandCheckCm)
    band.reset();
  const double frontEdge = band ? band->topRow : hemEdge;
  const double hemH = frontHemHeightCm(c, frontEdge, axisCol);
  out.landmarks.push_back({"hem_centre", {static_cast<double>(axisCol), frontEdge}});
  if (band) {
    std::ostringstream msg;
    msg << std::fixed << std::setprecision(1) << "hem: the hem is not level: a dark band "
        << band->depthCm
        << " cm deep lies across its middle just above its lowest edge (the inside of a "
           "high-low hem's back, below its front?); its length and round are read at the band's "
           "top, the front's hem";
    out.warnings.push_back(msg.str());
  } else if (const HemLevel level = hemLevel(c, hemEdge, axisCol); level.dropCm > kHemLevelDropCm) {
    std::ostringstream msg;
    msg << std::fixed << std::setprecision(1) << "hem: the hem is not level: ";
    if (std::abs(level.shiftCm) > kHemSlantShare * level.widthCm)
      msg << "it slants " << level.dropCm << " cm lower toward the image's "
          << (level.shiftCm < 0 ? "left" : "right")
          << " (an asymmetric hem?); its length and round are read at the centre line";
    else
      msg << "its centre hangs " << level.dropCm
          << " cm below where its full width ends (a curved hem, or a high-low hem's back "
             "below its front?); its length and round are read at that lowest edge: for a "
             "high-low hem the back's, not the front's";
    out.warnings.push_back(msg.str());
    // The skirt's flare is read where its full width ends: at the centre's hem one side of an
    // asymmetric hem has ended (three of four asymmetric hems read h_line so; stop 46).
    GarmentMeasurement scratch;
    Context quiet{c.mask, c.view, c.s, scratch, c.type};
    out.flareHemCircCm =
        circumferenceAt(quiet, view.heightOfRow(level.fullEdge) + kAboveHemCm, "hem_circ");
  }
  if (wants("hem_circ"))
    put("hem_circ", circumferenceAt(c, hemH + kAboveHemCm, "hem_circ"));
  if (wants("skirt_length"))
    put("skirt_length", view.waistCm() - hemH);
  if (wants("garment_length")) {
    // The garment's highest point is its neckline at the side neck. It is read just outside the
    // form's neck on both sides, where the silhouette can only be garment: over the neck itself
    // the form under the chin, shadowed by the head and tinted by light the garment throws back
    // on it, differs from the bare frame and joins the silhouette (a physical rig read
    // garment lengths 6-14 cm long so). Each side's first covered row is read at the depth of
    // the form's shoulder ridge beneath it (in perspective a camera below the shoulder sees a
    // top behind the axis plane lower: lengths read 0.6-0.7 cm short on two physical rigs
    // before), and the higher side is the top: a garment the colour of the form can lose a
    // notch of its shoulder on one side.
    const int offset = static_cast<int>(std::ceil(view.neckHalfWidthPx() + kOutsideNeckCm * c.s));
    const int fromRow =
        std::max(0, static_cast<int>(std::lround(view.rowOfHeight(view.neckSideCm() + 15.0))));
    std::vector<double> tops;
    for (const int col : {axisCol - offset, axisCol + offset}) {
      if (col < 0 || col >= garmentMask.cols)
        continue;
      if (const auto r = garmentTopRow(c, col, fromRow, static_cast<int>(hemEdge))) {
        const auto ridge = shoulderRidgeZ(c, col);
        tops.push_back(ridge ? heightAtDepthCm(c, *r, *ridge) : view.heightOfRow(*r));
        out.landmarks.push_back({col < axisCol ? "neck_left" : "neck_right",
                                 {static_cast<double>(col), static_cast<double>(*r)}});
      }
    }
    if (!tops.empty())
      put("garment_length", *std::max_element(tops.begin(), tops.end()) - hemH);
    else
      out.warnings.push_back("garment_length: the garment does not reach the side neck");
  }
  if (wants("sleeve_length")) {
    std::vector<double> lengths;
    for (int side = 0; side < 2; ++side)
      if (const auto& s = sleeves[static_cast<std::size_t>(side)]) {
        lengths.push_back(s->lengthCm);
        if (s->lengthCm > 0)
          out.landmarks.push_back({side == 0 ? "sleeve_end_left" : "sleeve_end_right", s->endPx});
      }
    if (lengths.empty())
      out.warnings.push_back("sleeve_length: the form has no arms");
    else
      // The longer of the two: a sleeve is lost from the silhouette in parts (a fabric the
      // colour of the form reads as exposed form, a notch cuts the arm off), but is not found
      // where there is none, and garments are symmetric.
      put("sleeve_length", *std::max_element(lengths.begin(), lengths.end()));
  }
  return out;
}

double partedLegsCm(const cv::Mat& garmentMask, const FormView& view) {
  if (garmentMask.size() != view.size() || garmentMask.type() != CV_8UC1)
    throw std::invalid_argument("partedLegs: the garment mask must be CV_8UC1 of the frame's size");
  const double s = view.pose().pxPerCm;
  const int axis = static_cast<int>(std::lround(view.axisXPx()));
  // The centre line counts as uncovered when a band of +-0.5 cm around it is; each leg must
  // show at least 2 cm of garment within 25 cm of the axis.
  const int half = std::max(1, static_cast<int>(std::lround(0.5 * s)));
  const int reach = static_cast<int>(std::lround(25.0 * s));
  const int minLeg = static_cast<int>(std::lround(2.0 * s));
  const int hipRow = std::max(0, static_cast<int>(std::lround(view.rowOfHeight(view.hipCm()))));
  int parted = 0, firstParted = 0;
  for (int r = hipRow; r < garmentMask.rows; ++r) {
    const uchar* m = garmentMask.ptr(r);
    bool centre = false;
    for (int x = std::max(0, axis - half); x <= std::min(garmentMask.cols - 1, axis + half); ++x)
      centre = centre || m[x] != 0;
    if (centre)
      continue;
    int left = 0, right = 0;
    for (int x = std::max(0, axis - reach); x < axis - half; ++x)
      left += m[x] != 0;
    for (int x = axis + half + 1; x <= std::min(garmentMask.cols - 1, axis + reach); ++x)
      right += m[x] != 0;
    if (left >= minLeg && right >= minLeg) {
      if (parted == 0)
        firstParted = r;
      ++parted;
    }
  }
  if (parted > 0) {
    // Pants' legs continue the seat: just below where they part, their outer edges are about as
    // far apart as just above. "Legs" much narrower than the garment just above them are the
    // form's legs below a skirt's hem, in the skirt's shadow (a physical rig's A-line skirt read
    // as pants so).
    const int step = std::max(1, static_cast<int>(std::lround(kLegStepCm * s)));
    const auto above = outerWidthPx(garmentMask, firstParted - step, axis, reach);
    const auto below = outerWidthPx(garmentMask, firstParted + step, axis, reach);
    if (above && below && *below < kLegStepShare * *above)
      return 0.0;
  }
  return parted / s;
}

double coveredBelowCrotchCm(const cv::Mat& garmentMask, const FormView& view) {
  if (garmentMask.size() != view.size() || garmentMask.type() != CV_8UC1)
    throw std::invalid_argument(
        "coveredBelowCrotch: the garment mask must be CV_8UC1 of the frame's size");
  if (!view.crotchCm())
    return 0.0;
  const double s = view.pose().pxPerCm;
  const int axis = static_cast<int>(std::lround(view.axisXPx()));
  const int crotchRow = static_cast<int>(std::lround(view.rowOfHeight(*view.crotchCm())));
  const int maxGap = std::max(1, static_cast<int>(std::lround(0.5 * s)));
  if (crotchRow < 0 || crotchRow >= garmentMask.rows)
    return 0.0;
  int last = -1, gap = 0;
  for (int r = crotchRow; r < garmentMask.rows; ++r) {
    if (maskCovers(garmentMask, r, axis)) {
      last = r;
      gap = 0;
    } else if (++gap > maxGap) {
      break;
    }
  }
  return last < 0 ? 0.0 : (last + 1 - crotchRow) / s;
}

// Holds the cached table alive (its type is this file's own).
struct FormDepthTable {
  std::shared_ptr<const void> table;
};

std::shared_ptr<const FormDepthTable> formDepthTable(const FormView& view) {
  return std::make_shared<const FormDepthTable>(FormDepthTable{depthTable(view)});
}

}  // namespace garmcap::pipeline
