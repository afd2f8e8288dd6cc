#include "garmcap/sim/garment_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <sstream>
#include <stdexcept>

#include "garmcap/calib/slicer.h"
#include "garmcap/drafts/file_io.h"
#include "garmcap/sim/form_generator.h"

namespace garmcap::sim {

using calib::FormView;
using calib::RowSection;

namespace {

// Skirts and pants: the waistband's top edge sits this far above the form's waist.
constexpr double kWaistbandRiseCm = 2.0;

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(1);
  s << std::fixed << v;
  return s.str();
}

double need(const GarmentSpec& spec, const std::string& name) {
  const auto it = spec.measurements.find(name);
  if (it == spec.measurements.end()) {
    throw std::invalid_argument("garment " + spec.type + " has no '" + name + "' measurement");
  }
  return it->second;
}

std::string attr(const GarmentSpec& spec, const std::string& name) {
  const auto it = spec.attributes.find(name);
  return it == spec.attributes.end() ? std::string() : it->second;
}

struct Knot {
  double h;
  double c;
};

// Measured circumferences of the body part of the garment, highest first.
std::vector<Knot> torsoKnots(const GarmentSpec& spec, const FormView& view,
                             const GarmentHeights& gh) {
  std::vector<Knot> k;
  const std::string& t = spec.type;
  if (t == "top" || t == "dress")
    k.push_back({view.bustCm(), need(spec, "bust_circ")});
  k.push_back({view.waistCm(), need(spec, "waist_circ")});
  if (t != "top")
    k.push_back({view.hipCm(), need(spec, "hip_circ")});
  if (t != "pants")
    k.push_back({gh.hemCm, need(spec, "hem_circ")});
  return k;
}

double circFromKnots(const std::vector<Knot>& k, double h) {
  for (const auto& kn : k) {
    if (std::abs(h - kn.h) <= kKnotPlateauCm)
      return kn.c;
  }
  if (h >= k.front().h)
    return k.front().c;
  if (h <= k.back().h)
    return k.back().c;
  for (std::size_t i = 0; i + 1 < k.size(); ++i) {
    const double hA = k[i].h - kKnotPlateauCm, hB = k[i + 1].h + kKnotPlateauCm;
    if (h <= k[i].h && h >= k[i + 1].h) {
      if (hA <= hB)
        return std::abs(h - k[i].h) < std::abs(h - k[i + 1].h) ? k[i].c : k[i + 1].c;
      const double t = (hA - h) / (hA - hB);
      return k[i].c + (k[i + 1].c - k[i].c) * t;
    }
  }
  return k.back().c;
}

// The form's legs seen from the side: per cm of height from `loCm` to `hiCm`, each leg's z
// extent, read at the nearest slice (slicing costs about a millisecond, so the legs are sliced
// once per garment, not per image row).
class LegSideView {
 public:
  LegSideView(const FormView& view, double loCm, double hiCm) : lo_(std::floor(loCm)) {
    const double axis = view.form().axisXCm();
    for (double h = lo_; h <= hiCm + 1.0; h += 1.0) {
      Extent e{};
      for (const auto& loop : view.form().section(h).torsoLoops)
        for (const auto& p : loop) {
          const int side = p.x() < axis ? 0 : 1;
          e.z0[side] = std::min(e.z0[side], p.y());
          e.z1[side] = std::max(e.z1[side], p.y());
        }
      rows_.push_back(e);
    }
  }
  // The deeper leg's z extent over the heights [loCm, hiCm] together (0 where no leg).
  double depthCm(double loCm, double hiCm) const {
    double best = 0;
    for (int side = 0; side < 2; ++side) {
      double z0 = 1e9, z1 = -1e9;
      for (std::size_t i = index(loCm); i <= index(hiCm) && i < rows_.size(); ++i) {
        z0 = std::min(z0, rows_[i].z0[side]);
        z1 = std::max(z1, rows_[i].z1[side]);
      }
      best = std::max(best, z1 - z0);
    }
    return best;
  }

 private:
  struct Extent {
    double z0[2] = {1e9, 1e9}, z1[2] = {-1e9, -1e9};
  };
  std::size_t index(double hCm) const {
    const long i = std::lround(hCm - lo_);
    return static_cast<std::size_t>(std::clamp<long>(i, 0, static_cast<long>(rows_.size()) - 1));
  }
  double lo_;
  std::vector<Extent> rows_;
};

// A leg's cloth hangs straight down from what stands deepest in the leg within this height above
// it (the knee and calf, for an opening near the ankle).
constexpr double kLegHangSpanCm = 20.0;
// A free tube hangs flattened front to back, this deep for its width: the physical rig's free
// straight legs measured on their settled cloth at the opening (docs/measurement_model.md, "Leg
// openings that hang from the knee": 14.6 / 16.3, 14.7 / 16.5, 14.0 / 16.8, 15.3 / 15.5 cm; "A
// free leg hangs flattened").
constexpr double kFreeTubeDepthShare = 0.9;

// How a garment hangs (docs/simulator.md, "Width model"). Its section at a height is a
// Minkowski sum of convex pieces: a hull of the form's sections, a disc of radius e (a uniform
// ease: perimeter + 2 pi e, width and depth + 2 e), a segment across (a skirt's sides swinging
// out: perimeter + 2 L, width + L) and a segment front to back (the front and back hanging off
// the bust: perimeter + 2 L, depth + L); at the bust a loose bodice's sides stand out as fins
// (FinnedSection), convex hulls rather than sums. Only the width is drawn; the shapes are what
// the physical rig's cloth does (docs/physical_rig.md), written without the measurer's ellipses.
constexpr double kBustEaseCm = 0.5;    // a bodice's uniform ease at the bust, at most
constexpr double kRoundEaseCm = 1.0;   // a loose bodice's round ease before its sides stand out
constexpr double kBodiceHang = 0.25;   // share of the bust's extra depth kept below it
constexpr double kSkirtSwingCm = 3.0;  // a skirt's side swing below the hip, at most
// A dress's hem hangs from its bodice (its front from the bust, its back from the shoulder blades
// and seat), so it is rounder than a skirt's of the same width: a front-to-back segment of this
// share of what the envelope of the form's sections from the hip to the bust is deeper than the
// hip (perimeter + 2 L: on the full form 2 L = 1.0 cm, the round the physical rigs' dress hems
// carry beyond a skirt's section of their width, which the measurer reads as an ellipse 0.15 of
// that excess deeper, kDressHemHangShare; docs/simulator.md, "Width model").
constexpr double kDressHemHang = 0.1;
constexpr double kLieOnFormCm = 0.5;  // a bodice with less ease than this does not hang
constexpr double kBustSidesCm = 8.0;  // the bust's side offset holds this far below it
// A sleeveless bodice below the bust: nothing holds its sides out, so only a share of its ease
// shows at them and the rest hangs off the bust and shoulder blades, front to back (the physical
// rig's sleeveless wovens: 1.0-1.8 cm a side at the waist for 16-25 cm of ease); on an armless
// torso form the sides stand further out for the same ease (the physical torso rigs).
constexpr double kSleevelessSideShare = 0.5;
constexpr double kArmlessSideShare = 0.7;

class HangingSections {
 public:
  explicit HangingSections(const FormView& view) {
    lo_ = view.crotchCm() ? *view.crotchCm() + 0.5 : view.hipCm() - 25.0;
    for (double h = lo_; h <= view.armpitCm() + 1e-9; h += 1.0) {
      const calib::FormSection sec = view.form().section(h);
      hulls_.push_back(sec.torsoLoops.empty() ? std::vector<Eigen::Vector2d>{}
                                              : calib::convexHull(sec.torsoLoops));
    }
  }
  struct Hull {
    double width = 0, depth = 0, perimeter = 0;
    std::vector<Eigen::Vector2d> polygon;  // (x, z) cm, counter-clockwise
  };
  // The hull of every section in [loCm, hiCm] (cm).
  Hull hull(double loCm, double hiCm) const {
    std::vector<Eigen::Vector2d> pts;
    loCm = std::max(loCm, lo_);
    hiCm = std::max(hiCm, loCm);
    for (std::size_t i = 0; i < hulls_.size(); ++i) {
      const double h = lo_ + static_cast<double>(i);
      if (h >= loCm - 0.5 && h <= hiCm + 0.5)
        pts.insert(pts.end(), hulls_[i].begin(), hulls_[i].end());
    }
    if (pts.size() < 3)
      return {};
    const auto poly = calib::convexHull({pts});
    double x0 = poly[0].x(), x1 = x0, z0 = poly[0].y(), z1 = z0;
    for (const auto& p : poly) {
      x0 = std::min(x0, p.x());
      x1 = std::max(x1, p.x());
      z0 = std::min(z0, p.y());
      z1 = std::max(z1, p.y());
    }
    return {x1 - x0, z1 - z0, calib::polygonPerimeter(poly), poly};
  }

 private:
  double lo_ = 0;
  std::vector<std::vector<Eigen::Vector2d>> hulls_;
};

// The convex hull of a polygon grown by a disc of radius `ease`, and the perimeter of its hull
// with a fin of length `fin` standing out beyond each end of its width, at the height (z) of
// that end.
class FinnedSection {
 public:
  FinnedSection(const std::vector<Eigen::Vector2d>& polygon, double ease) {
    constexpr int kDiscPoints = 32;
    calib::SliceLoop pts;
    pts.reserve(polygon.size() * kDiscPoints);
    for (const auto& p : polygon)
      for (int k = 0; k < kDiscPoints; ++k) {
        const double a = 2 * std::numbers::pi * k / kDiscPoints;
        pts.push_back(p + ease * Eigen::Vector2d(std::cos(a), std::sin(a)));
      }
    grown_ = calib::convexHull({pts});
    left_ = right_ = grown_.front();
    for (const auto& p : grown_) {
      if (p.x() < left_.x())
        left_ = p;
      if (p.x() > right_.x())
        right_ = p;
    }
  }
  double perimeter(double fin) const {
    calib::SliceLoop pts = grown_;
    pts.push_back(left_ - Eigen::Vector2d(fin, 0));
    pts.push_back(right_ + Eigen::Vector2d(fin, 0));
    return calib::polygonPerimeter(calib::convexHull({pts}));
  }

 private:
  std::vector<Eigen::Vector2d> grown_;
  Eigen::Vector2d left_, right_;
};

// Width beyond the form's section `f` (cm) of a garment of circumference c whose section is
// `base` (f, or a hull containing it) grown by a disc of radius `ease` and, for the rest, a fin
// at each side: the side seams of a loose bodice stand out from the form as fins of cloth, front
// and back panels meeting at them (the physical rig's settled cloth; docs/simulator.md, "Width
// model"). A fin adds width and little round: the hull gains the two tangents to its tip less
// the arc between their feet. A garment tighter than that is a Minkowski blend of f and it.
double sidesOut(const HangingSections::Hull& f, const HangingSections::Hull& base, double c,
                double ease) {
  const double pi = std::numbers::pi;
  const double grownW = base.width + 2 * ease, grownP = base.perimeter + 2 * pi * ease;
  if (c <= grownP || base.polygon.size() < 3) {
    const double t = std::clamp((c - f.perimeter) / std::max(grownP - f.perimeter, 1e-9), 0.0, 1.0);
    return t * (grownW - f.width);
  }
  // A loose bodice first rounds out to kRoundEaseCm all round, then stands out at its sides.
  const double roundP = base.perimeter + 2 * pi * kRoundEaseCm;
  if (c <= roundP)
    return base.width + 2 * (c - base.perimeter) / (2 * pi) - f.width;
  // The hull's perimeter grows with the fins' length (by less than twice it): bisect.
  const FinnedSection finned(base.polygon, kRoundEaseCm);
  double lo = 0, hi = c;
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    (finned.perimeter(mid) < c ? lo : hi) = mid;
  }
  return base.width + 2 * kRoundEaseCm - f.width + 2 * lo;
}

// Width beyond `f` of a garment grown from f by a uniform ease e: c = C_f + 2 pi e.
double easeOut(const HangingSections::Hull& f, double c) {
  return 2 * std::max(0.0, c - f.perimeter) / (2 * std::numbers::pi);
}

// Width beyond `f` of a bodice below the bust: f plus a disc of radius e plus a front-to-back
// segment of kBodiceHang of what the envelope `hang` is deeper than f grown by e (a loose
// garment's own ease takes over from the bust's hold as it grows), never longer than
// 2 (e - kLieOnFormCm): a garment with little ease lies on the form, it has no room to hang.
double bodiceOut(const HangingSections::Hull& f, const HangingSections::Hull& hang, double c) {
  const double dd = std::max(0.0, hang.depth - f.depth);
  auto perimeter = [&](double e) {
    const double segment =
        std::clamp(kBodiceHang * (dd - 2 * e), 0.0, std::max(0.0, 2 * (e - kLieOnFormCm)));
    return f.perimeter + 2 * std::numbers::pi * e + 2 * segment;
  };
  double lo = 0, hi = std::max(0.0, c - f.perimeter);  // perimeter(e) grows with e
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (perimeter(mid) < c ? lo : hi) = mid;
  }
  return 2 * lo;
}

// Width beyond `f` of a sleeveless bodice below the bust: f plus a disc of radius e, which is
// `share` of its ease, plus a front-to-back segment for the rest (perimeter 2 pi e + 2 L =
// c - C_f).
double sleevelessOut(const HangingSections::Hull& f, double c, double share) {
  return share * easeOut(f, c);
}

// Width beyond the hip section `f` of a skirt below the hip: the sides swing out first (up to
// kSkirtSwingCm across), then the hem flares as the hip section scaled.
double hemOut(const HangingSections::Hull& f, double c) {
  const double swing = std::min(kSkirtSwingCm, 0.5 * std::max(0.0, c - f.perimeter));
  const double k = std::max(1.0, (c - 2 * swing) / f.perimeter);
  return swing + (k - 1) * f.width;
}

// Fractional coverage of pixel centre x by the span [l, r].
float spanCover(double x, double l, double r) {
  return static_cast<float>(std::clamp(std::min(x + 0.5 - l, r - x + 0.5), 0.0, 1.0));
}

}  // namespace

nlohmann::json GarmentSpec::toJson() const {
  nlohmann::json m = nlohmann::json::object();
  for (const auto& [k, v] : measurements)
    m[k] = v;  // full precision: scene.json must re-render bit for bit
  return {{"type", type},
          {"attributes", attributes},
          {"measurements", m},
          {"details",
           {{"neckline", neckline},
            {"neck_depth_cm", neckDepthCm},
            {"sleeve_flare", sleeveFlare},
            {"thigh_ease", thighEase},
            {"hem_wave_cm", hemWaveCm},
            {"fold_seed", foldSeed}}}};
}

GarmentSpec GarmentSpec::fromJson(const nlohmann::json& j, const std::string& what) {
  GarmentSpec s;
  s.type = drafts::requireString(j, "type", what);
  std::vector<std::string> names;
  try {
    names = garmentMeasurementNames(s.type);
  } catch (const std::invalid_argument& e) {
    throw drafts::ParseError(what + ": field 'type': " + e.what());
  }
  const auto& a = drafts::requireField(j, "attributes", what);
  if (!a.is_object())
    throw drafts::ParseError(what + ": field 'attributes' must be an object");
  for (const auto& [k, v] : a.items()) {
    if (!v.is_string()) {
      throw drafts::ParseError(what + ": attribute '" + k + "' must be a string");
    }
    s.attributes[k] = v.get<std::string>();
  }
  const bool sleeved = s.type == "top" || s.type == "dress";
  const bool skirted = s.type == "skirt" || s.type == "dress";
  for (const auto& [k, v] : s.attributes) {
    const bool ok = (k == "sleeve" && sleeved && (v == "none" || v == "short" || v == "long")) ||
                    (k == "skirt" && skirted && (v == "a_line" || v == "h_line"));
    if (!ok) {
      throw drafts::ParseError(
          what + ": attribute '" + k + "' = '" + v + "' is not valid for a " + s.type +
          " (sleeve: none|short|long for top/dress; skirt: " + "a_line|h_line for skirt/dress)");
    }
  }
  if (sleeved && !s.attributes.count("sleeve")) {
    throw drafts::ParseError(what + ": a " + s.type + " needs attribute 'sleeve'");
  }
  if (skirted && !s.attributes.count("skirt")) {
    throw drafts::ParseError(what + ": a " + s.type + " needs attribute 'skirt'");
  }
  const auto& m = drafts::requireField(j, "measurements", what);
  if (!m.is_object())
    throw drafts::ParseError(what + ": field 'measurements' must be an object");
  for (const auto& [k, v] : m.items()) {
    if (std::find(names.begin(), names.end(), k) == names.end()) {
      throw drafts::ParseError(what + ": measurement '" + k + "' does not apply to a " + s.type);
    }
    if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0) {
      throw drafts::ParseError(what + ": measurement '" + k + "' must be a number >= 0 (cm)");
    }
    s.measurements[k] = v.get<double>();
  }
  for (const auto& n : names) {
    if (!s.measurements.count(n)) {
      throw drafts::ParseError(what + ": missing measurement '" + n + "' for a " + s.type);
    }
  }
  if (j.contains("details")) {
    const auto& d = j["details"];
    const std::string dw = what + " details";
    s.neckline = drafts::requireString(d, "neckline", dw);
    if (s.neckline != "round" && s.neckline != "v") {
      throw drafts::ParseError(dw + ": field 'neckline' must be round or v");
    }
    s.neckDepthCm = drafts::requireNumber(d, "neck_depth_cm", dw);
    s.sleeveFlare = drafts::requireNumber(d, "sleeve_flare", dw);
    s.thighEase = drafts::requireNumber(d, "thigh_ease", dw);
    s.hemWaveCm = drafts::requireNumber(d, "hem_wave_cm", dw);
    const auto& fs = drafts::requireField(d, "fold_seed", dw);
    if (!fs.is_number_unsigned())
      throw drafts::ParseError(dw + ": field 'fold_seed' must be a non-negative integer");
    s.foldSeed = fs.get<std::uint64_t>();
  }
  return s;
}

GarmentHeights garmentHeights(const GarmentSpec& spec, const FormView& view) {
  GarmentHeights g;
  if (spec.type == "top" || spec.type == "dress") {
    g.topCm = view.neckSideCm();
    g.hemCm = g.topCm - need(spec, "garment_length");
  } else if (spec.type == "skirt") {
    g.topCm = view.waistCm() + kWaistbandRiseCm;
    g.hemCm = view.waistCm() - need(spec, "skirt_length");
  } else {
    g.topCm = view.waistCm() + kWaistbandRiseCm;
    g.hemCm = view.waistCm() - need(spec, "outseam");
    g.crotchCm = g.hemCm + need(spec, "inseam");
  }
  return g;
}

double garmentCircAt(const GarmentSpec& spec, const FormView& view, double heightCm) {
  return circFromKnots(torsoKnots(spec, view, garmentHeights(spec, view)), heightCm);
}

void checkGarmentFits(const GarmentSpec& spec, const FormView& view) {
  const auto names = garmentMeasurementNames(spec.type);
  for (const auto& n : names)
    need(spec, n);
  const GarmentHeights gh = garmentHeights(spec, view);
  const double floor = view.form().minYCm();
  if (gh.hemCm < floor + 3) {
    throw std::invalid_argument("the " + spec.type + "'s hem would be " + fmt(gh.hemCm - floor) +
                                " cm above the floor: too long for this form");
  }
  if (spec.type == "top" && gh.hemCm > view.waistCm() - 3) {
    throw std::invalid_argument("garment_length " + fmt(need(spec, "garment_length")) +
                                " cm puts the top's hem above the form's waist");
  }
  if ((spec.type == "dress" || spec.type == "skirt") && gh.hemCm > view.hipCm() - 3) {
    throw std::invalid_argument("the " + spec.type + "'s hem would be above the form's hip");
  }
  if (spec.type == "top" && view.crotchCm() && gh.hemCm < *view.crotchCm() + 3) {
    throw std::invalid_argument("garment_length " + fmt(need(spec, "garment_length")) +
                                " cm reaches below the crotch: that is a dress, not a top");
  }
  if (spec.type == "dress") {
    const double expect = view.neckSideCm() - view.waistCm() + need(spec, "skirt_length");
    if (std::abs(expect - need(spec, "garment_length")) > 0.5) {
      throw std::invalid_argument("dress garment_length " + fmt(need(spec, "garment_length")) +
                                  " cm disagrees with skirt_length: on this form it must be " +
                                  fmt(expect) + " cm (side neck to waist + skirt_length)");
    }
  }
  // Circumferences against the form at their heights.
  const auto knots = torsoKnots(spec, view, gh);
  const std::vector<std::string> knotNames = [&] {
    std::vector<std::string> v;
    if (spec.type == "top" || spec.type == "dress")
      v.push_back("bust_circ");
    v.push_back("waist_circ");
    if (spec.type != "top")
      v.push_back("hip_circ");
    if (spec.type != "pants")
      v.push_back("hem_circ");
    return v;
  }();
  for (std::size_t i = 0; i < knots.size(); ++i) {
    const double h = knots[i].h < view.hipCm() ? view.hipCm() : knots[i].h;
    const auto sec = view.torsoAtHeight(h);
    if (!sec)
      throw std::invalid_argument("the form has no torso section at " + fmt(h) + " cm");
    if (knots[i].c < sec->circCm + kMinEaseCm) {
      throw std::invalid_argument(knotNames[i] + " " + fmt(knots[i].c) +
                                  " cm is smaller than the form's " + fmt(sec->circCm) + " cm + " +
                                  fmt(kMinEaseCm) +
                                  " cm ease there: the garment cannot be worn on this form");
    }
  }
  if (spec.type == "pants") {
    if (!view.crotchCm())
      throw std::invalid_argument("pants need a form with legs");
    if (gh.crotchCm > *view.crotchCm() + 0.01 || gh.crotchCm < *view.crotchCm() - 8) {
      throw std::invalid_argument(
          "outseam - inseam = " + fmt(need(spec, "outseam") - need(spec, "inseam")) +
          " cm puts the pants' crotch at " + fmt(gh.crotchCm) +
          " cm; it must be 0 to 8 cm below the form's crotch at " + fmt(*view.crotchCm()) + " cm");
    }
    const int hemRow = static_cast<int>(std::lround(view.rowOfHeight(gh.hemCm + 1.0)));
    for (int side = 0; side < 2; ++side) {
      const auto leg = view.legAtRow(hemRow, side);
      if (!leg)
        throw std::invalid_argument("the form has no leg at the pants' hem height");
      if (need(spec, "leg_opening_circ") < leg->circCm + kMinEaseCm) {
        throw std::invalid_argument("leg_opening_circ " + fmt(need(spec, "leg_opening_circ")) +
                                    " cm is smaller than the form's leg (" + fmt(leg->circCm) +
                                    " cm) + ease at the hem");
      }
    }
  }
  if (spec.type == "top" || spec.type == "dress") {
    const double sl = need(spec, "sleeve_length");
    const std::string sleeve = attr(spec, "sleeve");
    if ((sleeve == "none") != (sl == 0)) {
      throw std::invalid_argument("sleeve_length " + fmt(sl) + " cm disagrees with sleeve '" +
                                  sleeve + "' (0 exactly when sleeveless)");
    }
    if (sl > 0) {
      for (int side = 0; side < 2; ++side) {
        const auto& arm = view.arm(side);
        if (!arm)
          throw std::invalid_argument("sleeves need a form with arms");
        const double maxCm = (arm->tWristPx + 10.0 * view.pose().pxPerCm) / view.pose().pxPerCm;
        if (sl > maxCm) {
          throw std::invalid_argument("sleeve_length " + fmt(sl) +
                                      " cm is longer than the form's arm (" + fmt(maxCm) +
                                      " cm to 10 cm past the wrist)");
        }
      }
    }
  }
}

GarmentLayer layGarment(const GarmentSpec& spec, const FormView& view) {
  checkGarmentFits(spec, view);
  const cv::Size size = view.size();
  const double s = view.pose().pxPerCm;
  const GarmentHeights gh = garmentHeights(spec, view);
  const auto knots = torsoKnots(spec, view, gh);
  const bool upper = spec.type == "top" || spec.type == "dress";
  const bool aLine = attr(spec, "skirt") == "a_line";
  const bool sleeveless = upper && attr(spec, "sleeve") == "none";
  const double sideShare = view.arm(0) || view.arm(1) ? kSleevelessSideShare : kArmlessSideShare;
  const auto hipSec = view.torsoAtHeight(view.hipCm());
  const double hemRowC = view.rowOfHeight(gh.hemCm);
  const double topRowC = view.rowOfHeight(upper ? view.armpitCm() : gh.topCm);
  const double lowCm = spec.type == "pants" ? gh.crotchCm : gh.hemCm;
  const double lowRowC = view.rowOfHeight(lowCm);
  const double waveLambdaPx = 14.0 * s;
  const double waveAmpPx = aLine ? spec.hemWaveCm * s : 0.0;

  GarmentLayer g;
  g.coverage = cv::Mat1f(size, 0.f);
  // Band edges at each row (for the shoulder column above the armpit).
  double armpitL = 0, armpitR = 0;

  const HangingSections hanging(view);
  // Below the bust a bodice's sides keep the share of the form's width they stand off it at the
  // bust: they follow the form in as it narrows to the waist, rather than hang straight down
  // (34 tops and dresses of five physical rigs, 2 to 6 cm under the bust: the two sides'
  // stand-off changes by a median -0.6 cm while the form narrows by 1.9 cm; docs/simulator.md).
  double bustOutShare = 0;
  if (const auto b = view.torsoAtHeight(view.bustCm()); upper && b && b->widthPx() > 1) {
    HangingSections::Hull fb = hanging.hull(view.bustCm(), view.bustCm());
    fb.perimeter = b->circCm;
    const double cb = std::max(circFromKnots(knots, view.bustCm()), b->circCm + 1.0);
    bustOutShare = sidesOut(fb, hanging.hull(view.bustCm(), view.armpitCm()), cb, kBustEaseCm) /
                   (b->widthPx() / s);
  }
  double dressHemHangCm = 0;
  if (spec.type == "dress") {
    dressHemHangCm =
        kDressHemHang * std::max(0.0, hanging.hull(view.hipCm(), view.bustCm()).depth -
                                          hanging.hull(view.hipCm(), view.hipCm()).depth);
  }
  auto bandAt = [&](int row, double& l, double& r) -> bool {
    const double h = view.heightOfRow(row);
    std::optional<RowSection> ref;
    if (h >= view.hipCm()) {
      ref = view.torsoAtRow(row);
    } else if (hipSec) {
      ref = hipSec;  // skirts hang from the hip; they do not follow the legs
    }
    if (!ref)
      return false;
    double knotC = circFromKnots(knots, h);
    if (upper && h < view.bustCm() && h > view.waistCm() + kKnotPlateauCm) {
      // A bodice hangs straight from the bust for kBustSidesCm, then narrows to its waist.
      const double top = view.bustCm() - kBustSidesCm, bottom = view.waistCm() + kKnotPlateauCm;
      const double t = std::clamp((h - bottom) / std::max(top - bottom, 1e-9), 0.0, 1.0);
      knotC = circFromKnots(knots, view.waistCm()) +
              t * (circFromKnots(knots, view.bustCm()) - circFromKnots(knots, view.waistCm()));
    }
    const double c = std::max(knotC, ref->circCm + 1.0);
    const double refH = std::max(h, view.hipCm());
    HangingSections::Hull f = hanging.hull(refH, refH);
    f.perimeter = ref->circCm;  // the view's own tape at this height
    double out;                 // cm of width beyond the form's section
    const double waistLow = view.waistCm() - kKnotPlateauCm;
    const double hipHigh = view.hipCm() + kKnotPlateauCm;
    if (upper && (h >= waistLow || spec.type == "top")) {
      // A bodice: around the bust its extra width hangs at the sides over the envelope of the
      // sections up to the armpit (above the bust, of those above the row); lower down its
      // front and back hang partly off the bust. The side offset holds for kBustSidesCm below
      // the bust, then blends into the lower rule by the waist's plateau, so no step shows.
      const double bustLow = view.bustCm() - kBustSidesCm;
      const double waistHigh = view.waistCm() + kKnotPlateauCm;
      const auto hangHull = hanging.hull(h, view.armpitCm());
      const double atBust = h < view.bustCm() && bustOutShare > 0
                                ? bustOutShare * ref->widthPx() / s
                                : sidesOut(f, hangHull, c, kBustEaseCm);
      double below = bodiceOut(f, hangHull, c);
      if (sleeveless) {
        // Down to the waist's plateau; a top's lower part blends back to the bodice's rule by
        // its hem's plateau (the measurer's bodice rule reads the physical rigs' sleeveless
        // tops' hems better than the sleeveless one: hem mean 1.3-1.9 cm against 1.6-3.0 on
        // four rigs, docs/measurement_model.md, "A sleeveless bodice's waist hangs").
        const double hemHigh = std::min(waistLow, gh.hemCm + kKnotPlateauCm);
        const double u = std::clamp((waistLow - h) / std::max(waistLow - hemHigh, 1e-9), 0.0, 1.0);
        below = (1 - u) * sleevelessOut(f, c, sideShare) + u * below;
      }
      const double t = std::clamp((h - waistHigh) / std::max(bustLow - waistHigh, 1e-9), 0.0, 1.0);
      out = t * atBust + (1 - t) * below;
      // Above the bust the armhole is cut close to the body: the sides come in to the form's
      // own edge at the armpit (they would lie over the arm's root, which reads as a sleeve).
      if (h > view.bustCm())
        out *= std::clamp((view.armpitCm() - h) / std::max(view.armpitCm() - view.bustCm(), 1e-9),
                          0.0, 1.0);
    } else if (upper && h > hipHigh) {
      // A dress below its waist's plateau: from the bodice's hang to the skirt's uniform ease at
      // the hip's plateau.
      const double t = std::clamp((waistLow - h) / std::max(waistLow - hipHigh, 1e-9), 0.0, 1.0);
      const double bodice = sleeveless ? sleevelessOut(f, c, sideShare)
                                       : bodiceOut(f, hanging.hull(h, view.armpitCm()), c);
      out = (1 - t) * bodice + t * easeOut(f, c);
    } else if (h >= view.hipCm() - kKnotPlateauCm || spec.type == "pants") {
      out = easeOut(f, c);  // a uniform ease over the form's own section
    } else {
      // A skirt below the hip's plateau: from the uniform ease there to the hem's side swing
      // and flare at the hem's plateau; a dress's hem spends 2 L of its round on hanging
      // deeper (a segment front to back, perimeter + 2 L).
      const double top = view.hipCm() - kKnotPlateauCm, bottom = gh.hemCm + kKnotPlateauCm;
      const double t = std::clamp((top - h) / std::max(top - bottom, 1e-9), 0.0, 1.0);
      const double hang = std::min(t * dressHemHangCm, 0.5 * std::max(0.0, c - f.perimeter));
      out = (1 - t) * easeOut(f, c) + t * hemOut(f, c - 2 * hang);
    }
    const double w = ref->widthPx() + s * out;
    l = ref->centrePx() - 0.5 * w;
    r = ref->centrePx() + 0.5 * w;
    return true;
  };

  // (A) body band: from the armpit (tops, dresses) or the waistband down to the hem or crotch.
  const int rowStart = std::max(0, static_cast<int>(std::floor(topRowC)));
  const int rowEnd = std::min(
      size.height - 1,
      static_cast<int>(std::ceil((spec.type == "pants" ? lowRowC : hemRowC) + waveAmpPx + 1)));
  for (int y = rowStart; y <= rowEnd; ++y) {
    double l, r;
    if (!bandAt(y, l, r))
      continue;
    if (armpitR <= armpitL) {  // the first row of the band: the column above the armpit
      armpitL = l;
      armpitR = r;
    }
    float* cov = g.coverage.ptr<float>(y);
    const int x0 = std::max(0, static_cast<int>(std::floor(l)) - 1);
    const int x1 = std::min(size.width - 1, static_cast<int>(std::ceil(r)) + 1);
    const double mid = 0.5 * (l + r);
    for (int x = x0; x <= x1; ++x) {
      double bottom = spec.type == "pants" ? lowRowC : hemRowC;
      if (spec.type != "pants" && waveAmpPx > 0) {
        bottom += waveAmpPx * std::sin(2 * std::numbers::pi * (x - mid) / waveLambdaPx);
      }
      const double vTop = upper ? 1.0 : std::clamp(y - topRowC + 0.5, 0.0, 1.0);
      const double vBot = std::clamp(bottom - y + 0.5, 0.0, 1.0);
      cov[x] = std::max(cov[x], spanCover(x, l, r) * static_cast<float>(vTop * vBot));
    }
  }
  if (upper && armpitR <= armpitL) {
    throw std::invalid_argument("the form has no torso section just below the armpit");
  }

  // (B) shoulders: the form above the armpit, outside the neckline, not beyond the arms.
  if (upper) {
    const double neckRow = view.rowOfHeight(view.neckSideCm());
    const double a = view.neckHalfWidthPx();
    const double depthPx = spec.neckDepthCm * s;
    const double axis = view.axisXPx();
    for (int y = std::max(0, static_cast<int>(std::floor(neckRow)));
         y <= static_cast<int>(std::ceil(topRowC)) && y < size.height; ++y) {
      const float* fc = view.coverage().ptr<float>(y);
      float* cov = g.coverage.ptr<float>(y);
      for (int x = 0; x < size.width; ++x) {
        if (fc[x] <= 0.f)
          continue;
        const Eigen::Vector2d p(x, y);
        bool arm = false;
        for (int side = 0; side < 2; ++side) {
          const auto& ax = view.arm(side);
          if (!ax)
            continue;
          const bool outside = side == 0 ? x < armpitL : x > armpitR;
          if (outside && ax->t(p) > 0)
            arm = true;
        }
        if (arm)
          continue;
        const double dx = std::abs(x - axis);
        double neckY = neckRow;
        if (dx < a) {
          const double u = dx / a;
          neckY += depthPx * (spec.neckline == "v" ? (1.0 - u) : std::sqrt(1.0 - u * u));
        }
        const double v = std::clamp(y - neckY + 0.5, 0.0, 1.0);
        const double below = std::clamp(y - neckRow + 0.5, 0.0, 1.0);
        cov[x] = std::max(cov[x], fc[x] * static_cast<float>(std::min(v, below)));
      }
    }
  }

  // (C) sleeves along the arm axes.
  const double sleeveCm = upper ? need(spec, "sleeve_length") : 0.0;
  if (sleeveCm > 0) {
    const double L = sleeveCm * s;
    const double thick = 0.3 * s;
    const double sleeveTopRow = view.rowOfHeight(view.neckSideCm());
    for (int side = 0; side < 2; ++side) {
      const auto& ax = view.arm(side);
      if (!ax)
        continue;
      // Bounding box of the sleeve: the axis segment widened by the largest half-width.
      const double maxHw = (ax->halfWidthAt(0) + ax->halfWidthAt(L)) * spec.sleeveFlare + thick + 4;
      const Eigen::Vector2d e0 = ax->originPx - ax->dir * maxHw,
                            e1 = ax->originPx + ax->dir * (L + 2);
      const int x0 = std::max(0, static_cast<int>(std::min(e0.x(), e1.x()) - 2 * maxHw));
      const int x1 =
          std::min(size.width - 1, static_cast<int>(std::max(e0.x(), e1.x()) + 2 * maxHw));
      const int y0 = std::max(0, static_cast<int>(std::min(e0.y(), e1.y()) - 2 * maxHw));
      const int y1 =
          std::min(size.height - 1, static_cast<int>(std::max(e0.y(), e1.y()) + 2 * maxHw));
      for (int y = y0; y <= y1; ++y) {
        float* cov = g.coverage.ptr<float>(y);
        for (int x = x0; x <= x1; ++x) {
          const Eigen::Vector2d p(x, y);
          const double t = ax->t(p);
          if (t < -maxHw || t > L + 1)
            continue;
          const double tc = std::max(t, 0.0);
          const double flare = 1.0 + (spec.sleeveFlare - 1.0) * std::clamp(tc / L, 0.0, 1.0);
          const double hw = ax->halfWidthAt(tc) * flare + thick;
          const double d = ax->d(p) - ax->centreAt(tc);
          const double across = std::clamp(hw - std::abs(d) + 0.5, 0.0, 1.0);
          const double along = std::clamp(L - t + 0.5, 0.0, 1.0);
          // Above the shoulder tip only where the form is (the sleeve head lies on it), and
          // never above the side neck: the arm's axis, extended past the tip, runs up the neck.
          double head = 1.0;
          if (t < 0)
            head = y + 0.5 < sleeveTopRow ? 0.0 : view.coverage()(y, x);
          cov[x] = std::max(cov[x], static_cast<float>(across * along * head));
        }
      }
    }
  }

  // (D) pants legs from the crotch to the hem.
  if (spec.type == "pants") {
    const double opening = need(spec, "leg_opening_circ");
    const double thighRefCm = *view.crotchCm() - 5.0;
    double seatL = 0, seatR = 0;
    if (!bandAt(static_cast<int>(std::lround(lowRowC)), seatL, seatR)) {
      throw std::invalid_argument("the form has no hip section for the pants' seat");
    }
    const int thighRow = static_cast<int>(std::lround(view.rowOfHeight(thighRefCm)));
    const LegSideView legSide(view, gh.hemCm, thighRefCm);
    const int y0 = std::max(0, static_cast<int>(std::floor(lowRowC)));
    const int y1 = std::min(size.height - 1, static_cast<int>(std::ceil(hemRowC)) + 1);
    for (int side = 0; side < 2; ++side) {
      const auto thigh = view.legAtRow(thighRow, side);
      if (!thigh)
        throw std::invalid_argument("the form has no leg 5 cm below its crotch");
      const double thighCirc = thigh->circCm * spec.thighEase;
      for (int y = y0; y <= y1; ++y) {
        const double h = view.heightOfRow(y);
        const auto ref = h > thighRefCm ? thigh : view.legAtRow(y, side);
        if (!ref)
          continue;
        double c;
        if (h <= gh.hemCm + kKnotPlateauCm) {
          c = opening;
        } else {
          const double t = (gh.crotchCm - h) / (gh.crotchCm - gh.hemCm - kKnotPlateauCm);
          c = thighCirc + (opening - thighCirc) * std::clamp(t, 0.0, 1.0);
        }
        c = std::max(c, ref->circCm + 1.0);
        // The leg's section scaled to the tube's round, but no deeper than wide where the tube
        // hangs free of the leg: a cloth tube round a leg that is deeper than wide (the ankle,
        // 1.2-1.4 times) takes the leg's shape only while something holds it; once a round tube
        // of its circumference (c / pi across) clears the leg's side view over the
        // kLegHangSpanCm above (the calf and knee it hangs from), nothing holds it deeper than
        // it is wide, and it is at least c / pi wide (the independent physical rig's free legs
        // are 0.83-1.0 times as deep as wide at their openings, whatever leg is inside;
        // docs/simulator.md, Pants).
        double widthPx = ref->widthPx() * c / ref->circCm;
        if (h <= thighRefCm &&
            c / std::numbers::pi >= legSide.depthCm(h, std::min(h + kLegHangSpanCm, thighRefCm)))
          widthPx = std::max(widthPx, s * c / ellipsePerimeter(0.5, 0.5 * kFreeTubeDepthShare));
        const double hw = 0.5 * widthPx;
        double l = ref->centrePx() - hw, r = ref->centrePx() + hw;
        // The outer edge leaves the seat's line at the crotch and reaches the leg's own over
        // the next 10 cm (the thigh of real pants; not a measured width).
        const double blend = std::clamp((gh.crotchCm - h) / 10.0, 0.0, 1.0);
        if (side == 0)
          l = seatL + (l - seatL) * blend;
        else
          r = seatR + (r - seatR) * blend;
        const double gap = s * std::min(0.3 + 0.25 * std::max(0.0, gh.crotchCm - h), 3.0);
        if (side == 0)
          r = std::min(r, view.axisXPx() - gap);
        if (side == 1)
          l = std::max(l, view.axisXPx() + gap);
        const double vTop = std::clamp(y - lowRowC + 0.5, 0.0, 1.0);
        const double vBot = std::clamp(hemRowC - y + 0.5, 0.0, 1.0);
        float* cov = g.coverage.ptr<float>(y);
        const int xa = std::max(0, static_cast<int>(std::floor(l)) - 1);
        const int xb = std::min(size.width - 1, static_cast<int>(std::ceil(r)) + 1);
        for (int x = xa; x <= xb; ++x) {
          cov[x] = std::max(cov[x], spanCover(x, l, r) * static_cast<float>(vTop * vBot));
        }
      }
    }
  }

  // Normals, folds and fabric coordinates from the horizontal runs of the garment: each run is
  // shaded as the front of a tube (a cylinder across the run), folds hang from the top edge and
  // deepen towards the hem.
  g.normals = cv::Mat3f(size, cv::Vec3f(0, 0, 1));
  g.foldShade = cv::Mat1f(size, 0.f);
  g.uvCm = cv::Mat2f(size, cv::Vec2f(0, 0));
  const double topRow = view.rowOfHeight(gh.topCm);
  const double len = std::max(1.0, hemRowC - topRow);
  const double ph1 = static_cast<double>(spec.foldSeed % 1000) * 0.00628;
  const double ph2 = static_cast<double>((spec.foldSeed / 1000) % 1000) * 0.00628;
  for (int y = 0; y < size.height; ++y) {
    const float* cov = g.coverage.ptr<float>(y);
    int x = 0;
    while (x < size.width) {
      if (cov[x] <= 0.f) {
        ++x;
        continue;
      }
      const int a = x;
      while (x < size.width && cov[x] > 0.f)
        ++x;
      const int b = x - 1;
      const double mid = 0.5 * (a + b), hw = std::max(1.0, 0.5 * (b - a + 1));
      const double v = (y - topRow) / len;  // 0 at the top edge, 1 at the hem
      const double amp = std::clamp(0.25 + 0.75 * v, 0.0, 1.0) * (aLine ? 1.3 : 1.0);
      for (int i = a; i <= b; ++i) {
        const double u = std::clamp((i - mid) / hw, -0.999, 0.999);
        const double lambda = (aLine ? 9.0 + 6.0 * v : 7.0) * s;
        const double f =
            amp *
            (0.6 * std::sin(2 * std::numbers::pi * (i - view.axisXPx()) / lambda + ph1 + 2.0 * v) +
             0.4 * std::sin(2 * std::numbers::pi * (i - view.axisXPx()) / (0.47 * lambda) + ph2));
        const double nx = u + 0.25 * f;
        const double nz = std::sqrt(std::max(0.05, 1.0 - std::min(1.0, nx * nx)));
        g.normals(y, i) = cv::Vec3f(static_cast<float>(nx), 0.f, static_cast<float>(nz));
        g.foldShade(y, i) = static_cast<float>(f);
        g.uvCm(y, i) = cv::Vec2f(static_cast<float>(hw / s * std::asin(u)),
                                 static_cast<float>((y - topRow) / s + 0.15 * f));
      }
    }
  }
  return g;
}

}  // namespace garmcap::sim
