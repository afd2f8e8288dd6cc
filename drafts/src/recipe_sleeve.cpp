// Bunka set-in sleeve (research/drafting_blocks.md §4.1) with the cap fitted to the armhole
// the way FreeSewing's Brian does it (§4.4): the front and back slant lengths are solved so
// that each half of the cap is its armhole length plus its share of the cap ease.
#include <cmath>

#include "recipe_blocks.h"
#include "recipe_list.h"

namespace garmcap::drafts::detail {
namespace {

Point2 upward(const Point2& v) {
  Point2 n(-v.y(), v.x());
  return n.y() < 0 ? n : Point2(-n);
}

// Half cap from the underarm point to the top (front) or top to underarm (back).
Polyline frontCap(const Point2& top, double slant, double h, double q, double out, double in) {
  const Point2 uf = top + Point2(-std::sqrt(slant * slant - h * h), h);
  const Point2 u = (uf - top) / slant;
  const Point2 o = upward(u);
  const Point2 p1 = top + q * u + out * o;
  const Point2 mid = top + (slant / 2 + 1) * u;
  const Point2 p2 = uf - q * u - in * o;
  return curve({{uf, Point2(1, 0)},
                {p2, std::nullopt},
                {mid, std::nullopt},
                {p1, std::nullopt},
                {top, Point2(1, 0)}},
               kCapCount);
}

Polyline backCap(const Point2& top, double slant, double h, double q, double out, double in) {
  const Point2 ub = top + Point2(std::sqrt(slant * slant - h * h), h);
  const Point2 u = (ub - top) / slant;
  const Point2 o = upward(u);
  const Point2 p1 = top + q * u + out * o;
  const Point2 mid = top + (slant / 2 + 1) * u;
  const Point2 p2 = ub - q * u - in * o;
  return curve({{top, Point2(1, 0)},
                {p1, std::nullopt},
                {mid, std::nullopt},
                {p2, std::nullopt},
                {ub, Point2(1, 0)}},
               kCapCount);
}

// Slant length whose half cap has length `target`: the midpoint of a bisection on [lo, hi]
// down to 1e-5 cm (the cap grows with the slant). Each evaluation draws a whole cap curve and
// the bisection needs about 23, so the root is first bracketed tightly by regula falsi
// (Illinois variant, a handful of evaluations); the bisection is then replayed, taking its
// decisions from that bracket — a midpoint left of it has f < 0, right of it f > 0 — and
// evaluating only a midpoint that falls inside it. The result is bit for bit the plain
// bisection's, in about a third of the curve evaluations.
template <class F>
std::optional<double> solveSlant(F capOf, double lo, double hi, double target) {
  auto f = [&](double slant) { return polylineLength(capOf(slant)) - target; };
  const double fLo = f(lo), fHi = f(hi);
  if (fLo > 0 || fHi < 0)
    return std::nullopt;
  double a = lo, b = hi, fa = fLo, fb = fHi;
  int side = 0;
  for (int i = 0; i < 40 && b - a > 1e-7; ++i) {
    double c = (a * fb - b * fa) / (fb - fa);
    if (!(c > a && c < b))
      c = (a + b) / 2;
    const double fc = f(c);
    if (fc < 0) {
      a = c;
      fa = fc;
      if (side == -1)
        fb /= 2;  // Illinois: the end that stays twice in a row gets half its weight
      side = -1;
    } else {
      b = c;
      fb = fc;
      if (side == 1)
        fa /= 2;
      side = 1;
    }
  }
  // Margin against rounding noise in f (its slope is of order 1, the noise ~1e-13 cm).
  const double aSafe = a - 1e-9, bSafe = b + 1e-9;
  for (int i = 0; i < 50 && hi - lo > 1e-5; ++i) {
    const double m = (lo + hi) / 2;
    const bool below = m < aSafe ? true : (m > bSafe ? false : f(m) < 0);
    (below ? lo : hi) = m;
  }
  return (lo + hi) / 2;
}

}  // namespace

double bunkaCapHeight(const BodiceDraft& d, double factor) {
  return (d.yS - (d.spFClosed.y() + d.spB.y()) / 2) * 5.0 / 6.0 * factor;
}

SleeveDraft draftSleeve(DraftBuilder& b, const SleeveOptions& o) {
  SleeveDraft s;
  const double h = o.capHeight;
  b.require(h > 2, "sleeve cap height " + std::to_string(h) + " cm is too small");
  const Point2 T = b.point("sleeve_cap_top", o.origin);
  const double ah = o.fah + o.bah;
  s.easeFront = o.capEase * o.fah / ah;
  s.easeBack = o.capEase * o.bah / ah;
  const double q = o.fah / 4;
  auto fc = [&](double sl) { return frontCap(T, sl, h, q, o.outFront, o.inFront); };
  auto bc = [&](double sl) { return backCap(T, sl, h, o.bah / 4, o.outBack, o.inBack); };
  const auto sF = solveSlant(fc, h * 1.05 + 0.5, 3 * o.fah, o.fah + s.easeFront);
  const auto sB = solveSlant(bc, h * 1.05 + 0.5, 3 * o.bah, o.bah + s.easeBack);
  if (!sF || !sB) {
    b.refuse("no sleeve cap of height " + std::to_string(h) + " cm fits the armhole (" +
             std::to_string(ah) + " cm) with sleeve_cap_ease " + std::to_string(o.capEase) + " cm");
  }
  s.capFront = fc(*sF);
  s.capBack = bc(*sB);
  s.top = T;
  s.underFront = b.point("sleeve_underarm_front", s.capFront.front());
  s.underBack = b.point("sleeve_underarm_back", s.capBack.back());
  // Body of the sleeve: seams straight from the underarm points to the wrist points of a full
  // sleeve, hem centred between the underarm points so both seams have the same length.
  const double full = o.armLength;
  const double len = o.lengthFactor * full;
  b.require(len > h + 2, "sleeve_length " + std::to_string(o.lengthFactor) +
                             " gives a sleeve shorter than its cap (use 0 for sleeveless)");
  const double xc = (s.underFront.x() + s.underBack.x()) / 2;
  const double hw = o.wristOpening / 2;
  const Point2 wristF(xc - hw, T.y() + full), wristB(xc + hw, T.y() + full);
  const double t = (len - h) / (full - h);
  s.hemFront = b.point("sleeve_hem_front", pointAtFraction(s.underFront, wristF, t));
  s.hemBack = b.point("sleeve_hem_back", pointAtFraction(s.underBack, wristB, t));
  b.point("level_sleeve_hem", Point2(xc, T.y() + len));
  b.construction("sleeve_centre_line", T, Point2(T.x(), T.y() + len));
  b.construction("sleeve_biceps_line", s.underFront, s.underBack);
  b.construction("sleeve_front_slant", T, s.underFront);
  b.construction("sleeve_back_slant", T, s.underBack);
  const double yElbow = T.y() + full / 2 + 2.5;
  if (yElbow < T.y() + len) {
    b.construction(
        "sleeve_elbow_line",
        Point2(pointAtFraction(s.underFront, wristF, (yElbow - T.y() - h) / (full - h)).x(),
               yElbow),
        Point2(pointAtFraction(s.underBack, wristB, (yElbow - T.y() - h) / (full - h)).x(),
               yElbow));
  }
  b.contour("sleeve_cap_front", s.capFront);
  b.contour("sleeve_cap_back", s.capBack);
  b.contour("sleeve_seam_front", Polyline{s.underFront, s.hemFront});
  b.contour("sleeve_seam_back", Polyline{s.underBack, s.hemBack});
  b.contour("sleeve_hem", Polyline{s.hemFront, s.hemBack});
  return s;
}

void addSleevePanel(DraftBuilder& b, const SleeveDraft& s, const std::string& bodiceBack,
                    const Point2& backArmholeFrom, const Point2& backArmholeTo,
                    const std::string& bodiceFront, const Point2& frontArmholeFrom,
                    const Point2& frontArmholeTo) {
  Pattern& p = b.pattern();
  Polyline out;
  append(out, s.capBack);
  append(out, Polyline{s.hemBack, s.hemFront});
  append(out, s.capFront);
  Panel panel = makePanel("sleeve", out);
  panel.cutCount = 2;
  panel.cutOnFold = false;
  panel.grainline = grainline(s.top + Point2(0, 2), Point2(s.top.x(), s.hemFront.y() - 2));
  panel.notches.push_back(Notch{"cap_top", s.top});
  panel.notches.push_back(Notch{
      "armhole_front", pointAlong(s.capFront, 7 + s.easeFront * 7 / polylineLength(s.capFront))});
  panel.notches.push_back(
      Notch{"armhole_back", pointAlong(s.capBack, polylineLength(s.capBack) - 8 -
                                                      s.easeBack * 8 / polylineLength(s.capBack))});
  addPanelWithRegion(p, panel);
  addSeam(p, "sleeve_underarm", "sleeve", s.underFront, s.hemFront, "sleeve", s.underBack,
          s.hemBack);
  if (!bodiceBack.empty()) {
    addSeam(p, "armhole_back", bodiceBack, backArmholeFrom, backArmholeTo, "sleeve", s.top,
            s.underBack, s.easeBack, true);
    addSeam(p, "armhole_front", bodiceFront, frontArmholeFrom, frontArmholeTo, "sleeve", s.top,
            s.underFront, s.easeFront, true);
  }
}

void recipeSleeve(DraftBuilder& b) {
  BodiceOptions bo;
  bo.easeBust = b.design("ease_bust");
  bo.easeWaist = b.design("ease_waist");
  const BodiceDraft d = draftBodiceBlock(b, b.measurement("bust_circ"), b.measurement("waist_circ"),
                                         b.measurement("neck_back_to_waist_b"), bo);
  // The bodice is only the reference the cap is measured on: draw it grey.
  for (auto& l : b.pattern().lines)
    l.construction = true;
  SleeveOptions o;
  o.fah = d.fah;
  o.bah = d.bah;
  o.capHeight = bunkaCapHeight(d);
  o.capEase = b.design("sleeve_cap_ease");
  o.armLength = b.measurement("arm_shoulder_tip_to_wrist");
  o.lengthFactor = b.design("sleeve_length");
  o.wristOpening = b.measurement("arm_wrist_circ") + b.design("ease_wrist");
  o.origin = Point2(d.bw + 6 + d.fah, d.yS - o.capHeight);
  const SleeveDraft s = draftSleeve(b, o);
  addSleevePanel(b, s, "", {}, {}, "", {}, {});
}

}  // namespace garmcap::drafts::detail
