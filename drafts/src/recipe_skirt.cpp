// The skirt block (research/drafting_blocks.md §2.1, East-Asian/Bunka preset), its A-line side
// flare (§2.2, pivot at the hip point so the hip girth is kept) and the high-waist extension
// (§2.3) along the bodice side seam and darts.
#include <cmath>

#include "recipe_blocks.h"
#include "recipe_list.h"

namespace garmcap::drafts::detail {
namespace {

// Arc length along a left-to-right polyline where it crosses x.
double arcAtX(const Polyline& pl, double x) {
  auto hit = firstIntersection(pl, Line::vertical(x));
  return hit ? hit->sA : 0;
}

struct Piece {
  Polyline waist;  // left to right incl. darts
  std::vector<Dart> darts;
  Polyline side;  // side waist -> hip -> hem side (top to bottom)
  Polyline hem;   // left to right
};

// The waist of a skirt whose side intake is `s` (per side seam edge) with the side line moved
// `shift` toward the front at the hip (the back `shift` wider there, the front as much
// narrower).
struct SkirtWaist {
  Point2 hipB, hipF, swb, swf;
  Polyline sideB, sideF, waistBFine, waistFFine;
};

SkirtWaist skirtWaist(const SkirtOptions& o, double s, double shift) {
  const bool isHigh = o.waistRaise > 0;
  const double raise = isHigh ? 0 : o.sideRaise, drop = isHigh ? 0 : o.cbDrop;
  const double y0 = o.waistY, yH = o.waistY + o.hipLength;
  const Point2 cbw(o.cbX, y0 + drop), cfw(o.cfX, y0);
  SkirtWaist w;
  w.hipB = Point2(o.cbX + o.hipBack + shift, yH);
  w.hipF = Point2(o.cfX - o.hipFront + shift, yH);
  w.swb = Point2(w.hipB.x() - s, y0 - raise);
  w.swf = Point2(w.hipF.x() + s, y0 - raise);
  // Side curves (convex, vertical where they meet the hip line).
  w.sideB = sampleByArcLength(smoothCurve(Polyline{w.swb, w.hipB}, std::nullopt, Point2(0, 1)),
                              kSideCurveCount);
  w.sideF = sampleByArcLength(smoothCurve(Polyline{w.swf, w.hipF}, std::nullopt, Point2(0, 1)),
                              kSideCurveCount);
  // Waist curves, perpendicular to CB/CF and to the side curves.
  const Point2 tB = w.sideB[1] - w.sideB[0];
  const Point2 tF = w.sideF[1] - w.sideF[0];
  Point2 wB(tB.y(), -tB.x());
  if (wB.x() < 0)
    wB = -wB;
  Point2 wF(tF.y(), -tF.x());
  if (wF.x() < 0)
    wF = -wF;
  w.waistBFine =
      isHigh ? Polyline{cbw, w.swb} : curve({{cbw, Point2(1, 0)}, {w.swb, wB}}, kFineCurveCount);
  w.waistFFine =
      isHigh ? Polyline{w.swf, cfw} : curve({{w.swf, wF}, {cfw, Point2(1, 0)}}, kFineCurveCount);
  return w;
}

}  // namespace

std::optional<SkirtSideFit> fitSkirtSide(const SkirtOptions& o) {
  if (!o.backDartsAbove || !o.frontDartsAbove)
    return std::nullopt;
  // The skirt takes the darts of the piece above, so each waist must be the sewn waist plus
  // those intakes. The side intake (one for both pieces, so the side seams still match) and the
  // side line's place at the hip are solved for that by Newton's method; the hip girth is kept.
  auto total = [](const std::vector<SkirtOptions::MatchedDart>& ds) {
    double t = 0;
    for (const auto& d : ds)
      t += d.width;
    return t;
  };
  const double wantB = o.waistBack + total(*o.backDartsAbove);
  const double wantF = o.waistFront + total(*o.frontDartsAbove);
  auto residual = [&](double si, double sh) {
    const SkirtWaist w = skirtWaist(o, si, sh);
    return Point2(polylineLength(w.waistBFine) - wantB, polylineLength(w.waistFFine) - wantF);
  };
  SkirtSideFit fit;
  fit.sideIntake = std::min(o.hipBack - o.waistBack, o.hipFront - o.waistFront) / 3;
  for (int it = 0; it < 20; ++it) {
    const Point2 r0 = residual(fit.sideIntake, fit.shift);
    if (r0.norm() < 1e-7)
      return std::abs(fit.shift) < 4 ? std::optional(fit) : std::nullopt;
    constexpr double h = 1e-4;
    const Point2 ds = (residual(fit.sideIntake + h, fit.shift) - r0) / h;
    const Point2 dh = (residual(fit.sideIntake, fit.shift + h) - r0) / h;
    const double det = ds.x() * dh.y() - dh.x() * ds.y();
    if (std::abs(det) < 1e-9 || !std::isfinite(det))
      return std::nullopt;
    fit.sideIntake -= (r0.x() * dh.y() - dh.x() * r0.y()) / det;
    fit.shift -= (ds.x() * r0.y() - r0.x() * ds.y()) / det;
  }
  return std::nullopt;
}

SkirtDraft draftSkirt(DraftBuilder& b, const SkirtOptions& o, bool addSideSeam) {
  SkirtDraft r;
  const std::string& px = o.prefix;
  const double y0 = o.waistY, yH = o.waistY + o.hipLength, yHem = o.waistY + o.length;
  b.require(o.length > o.hipLength + 3, "skirt_length = " + std::to_string(o.length) +
                                            " cm must reach at least 3 cm below "
                                            "the hip line (waist_to_hip_b = " +
                                            std::to_string(o.hipLength) + " cm)");
  const double high = o.waistRaise;
  const bool isHigh = high > 0;
  const double drop = isHigh ? 0 : o.cbDrop;
  // Suppression: side intake the same on both pieces so the side seams match.
  const double xb = o.hipBack - o.waistBack, xf = o.hipFront - o.waistFront;
  b.require(xb > 0.8 && xf > 0.8,
            "waist_circ + ease_waist leaves no waist suppression against hip_circ + ease_hip "
            "(back " +
                std::to_string(xb) + " cm, front " + std::to_string(xf) + " cm)");
  double sideIntake = std::min(xb, xf) / 3, shift = 0;
  const bool matched = o.backDartsAbove.has_value() && o.frontDartsAbove.has_value();
  if (matched) {
    const auto fit = fitSkirtSide(o);
    b.require(fit.has_value(),
              "the skirt cannot take the bodice's waist darts (the waist does not fit the hip)");
    sideIntake = fit->sideIntake;
    shift = fit->shift;
  }
  const Point2 cbw(o.cbX, y0 + drop), cfw(o.cfX, y0);
  const SkirtWaist w = skirtWaist(o, sideIntake, shift);
  // Frame.
  const Point2 hipB = b.point(px + "_hip_side_back", w.hipB);
  const Point2 hipF = b.point(px + "_hip_side_front", w.hipF);
  b.point("level_hip", Point2(o.cbX, yH));
  b.construction(px + "_hip_line", Point2(o.cbX, yH), Point2(o.cfX, yH));
  b.construction(px + "_hem_line", Point2(o.cbX, yHem), Point2(o.cfX, yHem));
  b.construction(px + "_waist_line", Point2(o.cbX, y0), Point2(o.cfX, y0));
  b.construction(px + "_side_back_guide", Point2(hipB.x(), y0), Point2(hipB.x(), yHem));
  b.construction(px + "_side_front_guide", Point2(hipF.x(), y0), Point2(hipF.x(), yHem));
  const Point2 swb = b.point(px + "_waist_side_back", w.swb);
  const Point2 swf = b.point(px + "_waist_side_front", w.swf);
  b.point(px + "_waist_cb", cbw);
  b.point(px + "_waist_cf", cfw);
  const Polyline& sideB = w.sideB;
  const Polyline& sideF = w.sideF;
  const Polyline& waistBFine = w.waistBFine;
  const Polyline& waistFFine = w.waistFFine;
  // Darts: widths so that the waist seam without darts is exactly the target.
  const double dartB = polylineLength(waistBFine) - o.waistBack;
  const double dartF = polylineLength(waistFFine) - o.waistFront;
  b.require(dartB > 0.3 && dartF > 0.3, "waist too close to hip for the skirt darts");
  const double backW = hipB.x() - o.cbX, frontW = o.cfX - hipF.x();
  std::vector<double> bx =
      o.backDartX.value_or(std::vector<double>{o.cbX + backW / 3, o.cbX + 2 * backW / 3});
  std::vector<double> fx =
      o.frontDartX.value_or(std::vector<double>{o.cfX - 2 * frontW / 3, o.cfX - frontW / 3});
  const double apexB = y0 + 0.72 * o.hipLength, apexF = y0 + 0.5 * o.hipLength;
  std::vector<DartSpec> specsB = {
      {px + "_back_1", arcAtX(waistBFine, bx[0]), dartB / 2, apexB},
      {px + "_back_2", arcAtX(waistBFine, bx[1]), dartB / 2, apexB - 1}};
  std::vector<DartSpec> specsF = {
      {px + "_front_side", arcAtX(waistFFine, fx[0]), 0.55 * dartF, apexF},
      {px + "_front_cf", arcAtX(waistFFine, fx[1]), 0.45 * dartF, apexF}};
  if (matched) {
    // Each dart where its bodice dart is, at the same length from the seam's start: with equal
    // intakes before it, the legs then close at the same sewn distance on both pieces.
    b.require(
        o.backDartsAbove->size() == specsB.size() && o.frontDartsAbove->size() == specsF.size(),
        "the skirt takes two back and two front darts from the bodice");
    for (std::size_t i = 0; i < specsB.size(); ++i) {
      specsB[i].centreS = (*o.backDartsAbove)[i].centreS;
      specsB[i].width = (*o.backDartsAbove)[i].width;
    }
    for (std::size_t i = 0; i < specsF.size(); ++i) {
      specsF[i].centreS = (*o.frontDartsAbove)[i].centreS;
      specsF[i].width = (*o.frontDartsAbove)[i].width;
    }
  }
  auto back = openDarts(waistBFine, specsB);
  auto front = openDarts(waistFFine, specsF);
  if (!back || !front)
    b.refuse("the skirt darts do not fit in the waist");

  // Hem with the side flare: the hem side point turns about the hip point.
  const double below = yHem - yH;
  const double theta = radToDeg(std::atan2(o.hemFlare, below));
  const Point2 hsb =
      b.point(px + "_hem_side_back", rotateAbout(Point2(hipB.x(), yHem), hipB, -theta));
  const Point2 hsf =
      b.point(px + "_hem_side_front", rotateAbout(Point2(hipF.x(), yHem), hipF, theta));
  const Point2 cbh = b.point(px + "_hem_cb", Point2(o.cbX, yHem));
  const Point2 cfh = b.point(px + "_hem_cf", Point2(o.cfX, yHem));
  const Point2 dB = (hsb - hipB).normalized(), dF = (hsf - hipF).normalized();
  const Polyline hemB = curve({{cbh, Point2(1, 0)}, {hsb, Point2(dB.y(), -dB.x())}}, kHemCount);
  const Polyline hemF = curve({{hsf, Point2(dF.y(), -dF.x())}, {cfh, Point2(1, 0)}}, kHemCount);

  // Above the waist (high waist): side and darts follow the bodice, cut at the top line.
  Polyline topB, topF;  // CB top ... side top, side top ... CF top (with dart openings)
  std::vector<Dart> dartsB = back->darts, dartsF = front->darts;
  Point2 sideTopB, sideTopF;
  if (isHigh) {
    const BodiceDraft& bd = *o.bodice;
    const double yT = y0 - high;
    b.point("level_top", Point2(o.cbX, yT));
    auto upTo = [&](const Point2& from, const Point2& toward) {
      const Point2 u = (toward - from).normalized();
      return Point2(from + (high / std::abs(u.y())) * u);
    };
    sideTopB =
        b.point(px + "_top_side_back",
                upTo(swb, Point2(bd.side.x() - (bd.sideWaistBack.x() - swb.x()), bd.side.y())));
    sideTopF =
        b.point(px + "_top_side_front",
                upTo(swf, Point2(bd.side.x() + (swf.x() - bd.sideWaistFront.x()), bd.side.y())));
    const Point2 cbTop = b.point(px + "_top_cb", Point2(o.cbX, yT));
    const Point2 cfTop = b.point(px + "_top_cf", Point2(o.cfX, yT));
    // Bodice dart apexes above each skirt dart (back: e, d; front: b, a).
    auto buildTop = [&](const Point2& left, const Point2& right, std::vector<Dart>& darts,
                        const std::vector<BodiceDraft::WaistDart>& upper, Polyline& top,
                        Polyline& waistOut) {
      Polyline out;
      Polyline waist;
      append(out, left);
      for (std::size_t i = 0; i < darts.size(); ++i) {
        Dart& d = darts[i];
        const double apexUp = upper[i].apexY;
        const double depth = y0 - apexUp;
        b.require(depth > high + 1, "waist_raise reaches above the bodice dart tips");
        const double k = 1 - high / depth;
        const double cx = (d.leg1.x() + d.leg2.x()) / 2, w = d.leg2.x() - d.leg1.x();
        const Point2 t1(cx - k * w / 2, yT), t2(cx + k * w / 2, yT);
        append(out, t1);
        // The outline goes down the dart to the waist, to the skirt apex and back up.
        append(out, Polyline{d.leg1, d.apex, d.leg2, t2});
        d = Dart{d.name, d.apex, t1, t2};
      }
      append(out, right);
      top = out;
      waist = waistOut;
    };
    std::vector<BodiceDraft::WaistDart> upB = bd.backDarts, upF = bd.frontDarts;
    Polyline dummyB = back->points, dummyF = front->points;
    buildTop(cbTop, sideTopB, dartsB, upB, topB, dummyB);
    buildTop(sideTopF, cfTop, dartsF, upF, topF, dummyF);
    b.contour(px + "_top_back", Polyline{cbTop, sideTopB});
    b.contour(px + "_top_front", Polyline{sideTopF, cfTop});
    b.contour(px + "_side_back_upper", Polyline{sideTopB, swb});
    b.contour(px + "_side_front_upper", Polyline{sideTopF, swf});
  }

  // Contours of the draft.
  if (!isHigh) {
    b.contour(px + "_waist_back", back->points);
    b.contour(px + "_waist_front", front->points);
  } else {
    b.construction(px + "_waist_back", back->points);
    b.construction(px + "_waist_front", front->points);
  }
  b.contour(px + "_side_back", joined(sideB, Polyline{hsb}));
  b.contour(px + "_side_front", joined(sideF, Polyline{hsf}));
  b.contour(px + "_hem_back", hemB);
  b.contour(px + "_hem_front", hemF);
  b.contour(px + "_centre_back", Polyline{isHigh ? b.at(px + "_top_cb") : cbw, cbh});
  b.contour(px + "_centre_front", Polyline{isHigh ? b.at(px + "_top_cf") : cfw, cfh});

  // Panels.
  Pattern& p = b.pattern();
  Polyline ob;
  if (isHigh) {
    append(ob, topB);
    append(ob, swb);
  } else {
    append(ob, back->points);
  }
  append(ob, sideB);
  append(ob, hsb);
  append(ob, reversed(hemB));
  Panel pb = makePanel(px + "_back", ob);
  pb.darts = dartsB;
  pb.grainline = grainline(Point2(o.cbX + backW / 2, y0 + 3), Point2(o.cbX + backW / 2, yHem - 3));
  pb.cutCount = 2;
  pb.cutOnFold = false;
  pb.notches.push_back(Notch{"hip_back", hipB});
  Polyline of;
  if (isHigh) {
    append(of, topF);
    append(of, cfh);
  }
  if (!isHigh) {
    append(of, front->points);
    append(of, cfh);
  }
  append(of, reversed(hemF));
  append(of, hsf);
  append(of, reversed(sideF));
  if (isHigh)
    append(of, sideTopF);
  Panel pf = makePanel(px + "_front", of);
  pf.darts = dartsF;
  pf.grainline = grainline(Point2(o.cfX - 4, y0 + 3), Point2(o.cfX - 4, yHem - 3));
  pf.cutCount = 1;
  pf.cutOnFold = true;
  pf.notches.push_back(Notch{"hip_front", hipF});
  addPanelWithRegion(p, pb);
  addPanelWithRegion(p, pf);
  // The back is cut twice: its two halves are sewn together at the centre back.
  const Point2 cbTop = isHigh ? b.at(px + "_top_cb") : cbw;
  p.seams.push_back(
      SeamPair{px + "_centre_back", shortEdge(pb, cbTop, cbh), shortEdge(pb, cbTop, cbh), 0});
  if (addSideSeam) {
    addSeam(p, px + "_side", px + "_back", isHigh ? sideTopB : swb, hsb, px + "_front",
            isHigh ? sideTopF : swf, hsf);
  }
  r.cbWaist = cbw;
  r.cfWaist = cfw;
  r.sideWaistBack = swb;
  r.sideWaistFront = swf;
  r.hipBack = hipB;
  r.hipFront = hipF;
  r.hemSideBack = hsb;
  r.hemSideFront = hsf;
  r.cbHem = cbh;
  r.cfHem = cfh;
  return r;
}

void recipeSkirt(DraftBuilder& b) {
  const double W = b.measurement("waist_circ"), H = b.measurement("hip_circ");
  const double hl = b.measurement("waist_to_hip_b");
  SkirtOptions o;
  const double wd = (H + b.design("ease_hip")) / 2;
  o.cbX = 0;
  o.cfX = wd;
  o.waistY = 0;
  o.hipLength = hl;
  o.length = b.design("skirt_length");
  o.hipBack = wd / 2 - 1;
  o.hipFront = wd / 2 + 1;
  const double quarterW = (W + b.design("ease_waist")) / 4;
  o.waistBack = quarterW - 1;
  o.waistFront = quarterW + 1;
  o.hemFlare = b.design("hem_flare");
  b.point("level_waist", Point2(0, 0));
  draftSkirt(b, o);
}

}  // namespace garmcap::drafts::detail
