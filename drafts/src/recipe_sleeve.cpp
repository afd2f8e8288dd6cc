// Bunka set-in sleeve (research/drafting_blocks.md §4.1) with the cap fitted to the armhole
// the way FreeSewing's Brian does it (§4.4): the front and back slant lengths are solved so
// that each half of the cap is its armhole length plus its share of the cap ease.
#include <algorithm>
#include <cmath>
#include <map>

#include "garmcap/drafts/panel_measure.h"
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

// Shortest sleeve drafted (cm from the cap top); anything shorter is no sleeve.
constexpr double kMinSleeveCm = 2.0;
// An underarm seam shorter than this is not sewn: such a sleeve is drafted as a cap sleeve
// ending at the underarm (its length is then short of the request by less than this).
constexpr double kMinUnderarmSeamCm = 0.1;

// The part of a half cap running from its underarm end to the cap top (`cap` from the
// underarm to the top) that lies above y = yHem: from the last crossing of that level to the
// top. std::nullopt when the cap never reaches the level.
std::optional<Polyline> capAbove(const Polyline& cap, double yHem) {
  for (std::size_t i = cap.size() - 1; i > 0; --i) {
    const Point2& lo = cap[i - 1];  // nearer the underarm
    const Point2& hi = cap[i];
    if (lo.y() >= yHem && hi.y() <= yHem) {
      const double span = lo.y() - hi.y();
      const double f = span > 1e-12 ? (lo.y() - yHem) / span : 0.0;
      Polyline part{lo + f * (hi - lo)};
      for (std::size_t k = i; k < cap.size(); ++k)
        append(part, cap[k]);
      if (part.size() < 2)
        return std::nullopt;
      return part;
    }
  }
  return std::nullopt;
}

// Puts a corner on the edge from -> to of `panelName` at sewn arc length `s` from `from`
// (dart openings in the edge are skipped, as sewnEdgeLength does) and returns it; the panel's
// own draft region gets the same outline. The run of free vertices between two fixed ones
// (the edge's ends, dart legs and apex) that holds the point is resampled along itself so that
// the point is the run's middle vertex: the vertex count stays that of a sleeved bodice, and
// the corner has the same index in every size, so DSW grading finds the seam's end where the
// target draft put it. A point within kSnapCm of a fixed vertex is that vertex (no sliver
// edges). std::nullopt when the edge is shorter than `s` or the run has no free vertex.
std::optional<Point2> markOnEdge(Pattern& p, const std::string& panelName, const Point2& from,
                                 const Point2& to, double s) {
  constexpr double kSnapCm = 0.15;
  Panel* panel = nullptr;
  for (auto& x : p.panels)
    panel = x.name == panelName ? &x : panel;
  if (!panel)
    return std::nullopt;
  const EdgeRef e = shortEdge(*panel, from, to);
  const int n = static_cast<int>(panel->outline.size());
  std::vector<int> idx;
  for (int i = e.from;; i = (i + 1) % n) {
    idx.push_back(i);
    if (i == e.to)
      break;
  }
  if (e.from != vertexIndex(*panel, from))
    std::reverse(idx.begin(), idx.end());
  auto at = [&](std::size_t k) -> Point2& {
    return panel->outline[static_cast<std::size_t>(idx[k])];
  };
  auto isDartVertex = [&](const Point2& v) {
    for (const auto& d : panel->darts) {
      if ((v - d.leg1).norm() < 1e-6 || (v - d.leg2).norm() < 1e-6 || (v - d.apex).norm() < 1e-6)
        return true;
    }
    return false;
  };
  auto fixed = [&](std::size_t k) { return k == 0 || k + 1 == idx.size() || isDartVertex(at(k)); };
  double walked = 0;
  std::size_t k = 0;
  while (k + 1 < idx.size()) {
    // A dart opening (leg, apex, leg) is closed when sewn: no length.
    if (k + 2 < idx.size() && isDartVertex(at(k)) && isDartVertex(at(k + 1)) &&
        isDartVertex(at(k + 2))) {
      k += 2;
      continue;
    }
    // The run from fixed vertex k to the next fixed vertex.
    std::size_t end = k + 1;
    while (!fixed(end))
      ++end;
    Polyline run;
    for (std::size_t j = k; j <= end; ++j)
      run.push_back(at(j));
    const double len = polylineLength(run);
    if (walked + len < s - 1e-9) {
      walked += len;
      k = end;
      continue;
    }
    const double sr = s - walked;
    if (sr < kSnapCm)
      return at(k);
    if (len - sr < kSnapCm)
      return at(end);
    if (end - k < 2)
      return std::nullopt;  // no free vertex to put the corner on
    const std::size_t mid = k + (end - k) / 2;
    const Polyline first = resample(subPolyline(run, 0, sr), static_cast<int>(mid - k + 1));
    const Polyline second = resample(subPolyline(run, sr, len), static_cast<int>(end - mid + 1));
    std::map<int, Point2> moved;  // outline index -> new position
    for (std::size_t j = 1; j < first.size(); ++j)
      moved[idx[k + j]] = first[j];
    for (std::size_t j = 1; j + 1 < second.size(); ++j)
      moved[idx[mid + j]] = second[j];
    for (const auto& [i, q] : moved)
      panel->outline[static_cast<std::size_t>(i)] = q;
    for (auto& r : p.regions) {
      if (r.name == panelName && r.polygon.size() == panel->outline.size())
        r.polygon = panel->outline;
    }
    return at(mid);
  }
  return std::nullopt;
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
  s.capFrontFull = polylineLength(s.capFront);
  s.capBackFull = polylineLength(s.capBack);
  const double full = o.armLength;
  const double len = o.lengthFactor * full;
  b.require(len >= kMinSleeveCm, "sleeve_length " + std::to_string(o.lengthFactor) +
                                     " gives a sleeve of " + std::to_string(len) +
                                     " cm, shorter than " + std::to_string(kMinSleeveCm) +
                                     " cm (use 0 for sleeveless)");
  const double xc = (s.underFront.x() + s.underBack.x()) / 2;
  s.capOnly = len < h + kMinUnderarmSeamCm;
  // A cap sleeve ends at the requested level, or at the underarm when the request lies less
  // than kMinUnderarmSeamCm below it.
  const double depth = s.capOnly ? std::min(len, h) : len;
  b.point("level_sleeve_hem", Point2(xc, T.y() + depth));
  b.construction("sleeve_centre_line", T, Point2(T.x(), T.y() + depth));
  b.construction("sleeve_biceps_line", s.underFront, s.underBack);
  b.construction("sleeve_front_slant", T, s.underFront);
  b.construction("sleeve_back_slant", T, s.underBack);
  if (s.capOnly) {
    // Cap sleeve: the block's cap cut by the horizontal hem line; the cap halves keep their
    // vertex count (resampled), the lower cap stays in the draft as a construction line.
    const double yHem = T.y() + depth;
    b.construction("sleeve_cap_front_full", s.capFront);
    b.construction("sleeve_cap_back_full", s.capBack);
    const auto front = capAbove(s.capFront, yHem);
    const auto back = capAbove(reversed(s.capBack), yHem);
    b.require(front && back, "sleeve cap does not reach the hem level of a " + std::to_string(len) +
                                 " cm cap sleeve");
    s.capFront = resample(*front, kCapCount);
    s.capBack = reversed(resample(*back, kCapCount));
    s.hemFront = b.point("sleeve_hem_front", s.capFront.front());
    s.hemBack = b.point("sleeve_hem_back", s.capBack.back());
    s.hemLine = divideSegment(s.hemBack, s.hemFront, 3);
    b.contour("sleeve_cap_front", s.capFront);
    b.contour("sleeve_cap_back", s.capBack);
    b.contour("sleeve_hem", s.hemLine);
    return s;
  }
  // Body of the sleeve: seams straight from the underarm points to the wrist points of a full
  // sleeve, hem centred between the underarm points so both seams have the same length. A
  // shorter sleeve is this block cut at its length: the seams shorten and the hem is the
  // block's width at that level.
  const double hw = o.wristOpening / 2;
  const Point2 wristF(xc - hw, T.y() + full), wristB(xc + hw, T.y() + full);
  const double t = (len - h) / (full - h);
  s.hemFront = b.point("sleeve_hem_front", pointAtFraction(s.underFront, wristF, t));
  s.hemBack = b.point("sleeve_hem_back", pointAtFraction(s.underBack, wristB, t));
  s.hemLine = Polyline{s.hemBack, s.hemFront};
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
  append(out, s.hemLine);
  append(out, s.capFront);
  Panel panel = makePanel("sleeve", out);
  panel.cutCount = 2;
  panel.cutOnFold = false;
  const double hemY = std::max(s.hemFront.y(), s.hemBack.y());
  panel.grainline = s.capOnly ? grainline(s.top, Point2(s.top.x(), hemY))
                              : grainline(s.top + Point2(0, 2), Point2(s.top.x(), hemY - 2));
  panel.notches.push_back(Notch{"cap_top", s.top});
  // Armhole notches at their places on the whole cap (7 cm above the front underarm, 8 cm above
  // the back one, plus the ease); a cap sleeve keeps those that lie on its part of the cap.
  const double cutFront = s.capFrontFull - polylineLength(s.capFront);
  const double cutBack = s.capBackFull - polylineLength(s.capBack);
  const double notchFront = 7 + s.easeFront * 7 / s.capFrontFull - cutFront;
  const double notchBack =
      polylineLength(s.capBack) - (8 + s.easeBack * 8 / s.capBackFull - cutBack);
  if (notchFront > 0.5)
    panel.notches.push_back(Notch{"armhole_front", pointAlong(s.capFront, notchFront)});
  if (notchBack < polylineLength(s.capBack) - 0.5 && notchBack - kDoubleNotchGapCm > 0.5)
    addDoubleNotch(panel, "armhole_back", s.capBack, notchBack);
  addPanelWithRegion(p, panel);
  if (!s.capOnly) {
    addSeam(p, "sleeve_underarm", "sleeve", s.underFront, s.hemFront, "sleeve", s.underBack,
            s.hemBack);
  }
  if (bodiceBack.empty())
    return;
  if (!s.capOnly) {
    addSeam(p, "armhole_back", bodiceBack, backArmholeFrom, backArmholeTo, "sleeve", s.top,
            s.underBack, s.easeBack, true);
    addSeam(p, "armhole_front", bodiceFront, frontArmholeFrom, frontArmholeTo, "sleeve", s.top,
            s.underFront, s.easeFront, true);
    return;
  }
  // Cap sleeve: each part of the cap is sewn to the armhole from the shoulder down, easing in
  // its share of the cap ease (the whole cap's ease in proportion to length); the armhole
  // below it is finished on its own. The bodice gets a corner where the sleeve ends.
  auto sewPart = [&](const std::string& seam, const std::string& bodice, const Point2& from,
                     const Point2& to, const Polyline& part, double fullCap,
                     const Point2& sleeveEnd) {
    const Panel& bp = p.panel(bodice);
    const double armhole = sewnEdgeLength(bp, shortEdge(bp, from, to));
    const double partLen = polylineLength(part);
    const double onBodice = partLen * armhole / fullCap;
    const auto mark = markOnEdge(p, bodice, from, to, onBodice);
    b.require(mark.has_value(), "no corner of '" + bodice + "' can end the cap sleeve's " + seam +
                                    " seam " + std::to_string(onBodice) + " cm below the shoulder");
    // A notch where the sleeve ends, so the bodice shows how far to set it in.
    for (auto& x : p.panels) {
      if (x.name == bodice)
        x.notches.push_back(Notch{"cap_sleeve_end", *mark});
    }
    addSeam(p, seam, bodice, from, *mark, "sleeve", s.top, sleeveEnd, partLen - onBodice, true);
  };
  sewPart("armhole_back", bodiceBack, backArmholeFrom, backArmholeTo, s.capBack, s.capBackFull,
          s.hemBack);
  sewPart("armhole_front", bodiceFront, frontArmholeFrom, frontArmholeTo, s.capFront,
          s.capFrontFull, s.hemFront);
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
