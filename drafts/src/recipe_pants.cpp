// Bunka-school women's trousers (research/drafting_blocks.md §5.1). Front frame: x = 0 at the
// side line, + toward CF; y = 0 at the waist line, down. The back is drawn on the same frame
// (as on a trace of the front), as the book does.
//
// Departures from the book, each so that the garment measures what it declares:
// * the back hip width (H + ease)/4 is taken horizontally on the hip line from the back
//   crotch seam (book: perpendicular to the seam from 2 cm above), so hip = H + ease exactly;
// * the back crotch point height is solved so the back inseam equals the front inseam (book:
//   0.5-1 cm lower and eased), and the back side-waist raise so the outseams are equal;
// * the side waist moves out when the waist is large, keeping at least 1 cm of darts;
// * lengths and offsets of the crotch extension scale with the frame (q).
#include <cmath>

#include "recipe_blocks.h"
#include "recipe_list.h"

namespace garmcap::drafts::detail {
namespace {

template <class F>
std::optional<double> bisect(F f, double lo, double hi) {
  double fl = f(lo), fh = f(hi);
  if (fl * fh > 0)
    return std::nullopt;
  for (int i = 0; i < 60 && hi - lo > 1e-6; ++i) {
    const double m = (lo + hi) / 2, fm = f(m);
    if ((fm < 0) == (fl < 0)) {
      lo = m;
      fl = fm;
    } else {
      hi = m;
    }
  }
  return (lo + hi) / 2;
}

Point2 perpPlusX(const Point2& t) {
  Point2 n(t.y(), -t.x());
  return n.x() >= 0 ? n : Point2(-n);
}

struct Leg {
  Polyline inseam, side, waistFine, crotch;
  Point2 sideWaist, crotchPoint, kneeIn, kneeOut, hemIn, hemOut;
};

}  // namespace

void recipePants(DraftBuilder& b) {
  const double W = b.measurement("waist_circ"), H = b.measurement("hip_circ");
  const double hl = b.measurement("waist_to_hip_b"), br = b.measurement("rise_length_side");
  const double tl = b.design("pants_length") * b.measurement("leg_waist_side_to_floor");
  const double eW = b.design("ease_waist"), eH = b.design("ease_hip");
  b.require(br > hl + 2, "rise_length_side = " + std::to_string(br) +
                             " cm must be at least 2 cm longer than waist_to_hip_b = " +
                             std::to_string(hl) + " cm");
  b.require(tl > br + 12, "pants_length gives trousers shorter than the rise plus 12 cm");
  const double w = (H + eH) / 4, q = w / 4;
  // 1-3. Frame, crotch point, crease.
  const Point2 a = b.point("crotch_corner_front", Point2(w, br));
  const Point2 bF = b.point("crotch_point_front", Point2(w + q, br));
  const Point2 c = b.point("hip_cf", Point2(w, hl));
  const double xCr = (w + q) / 2;
  b.point("level_waist", Point2(0, 0));
  b.point("level_hip", Point2(0, hl));
  b.point("level_crotch", Point2(0, br));
  b.construction("side_line", Point2(0, -2), Point2(0, tl));
  b.construction("waist_line", Point2(0, 0), Point2(w + q, 0));
  b.construction("hip_line", Point2(0, hl), Point2(w, hl));
  b.construction("crotch_line", Point2(-q, br), Point2(w + q + q, br));
  b.construction("cf_line", Point2(w, 0), a);
  b.construction("crease_line", Point2(xCr, 0), Point2(xCr, tl));
  b.construction("hem_line", Point2(-2, tl), Point2(w + q + 2, tl));
  // 4-5. Knee line, inseam hollow, knee symmetric about the crease.
  const double il = tl - br;
  const double yK = br + il / 2 - 4;
  b.require(yK > br + 3, "trousers too short for a knee line");
  b.construction("knee_line", Point2(-2, yK), Point2(w + q + 2, yK));
  const double hemHalf = b.design("hem_width") / 2;
  const Point2 hemIn = b.point("hem_in_front", Point2(xCr + hemHalf, tl));
  const Point2 hemOut = b.point("hem_out_front", Point2(xCr - hemHalf, tl));
  const double tK = (yK - br) / (tl - br);
  const Point2 kneeIn =
      b.point("knee_in_front", pointAtFraction(bF, hemIn, tK) - Point2(0.85 * q / 5.875, 0));
  const Point2 kneeOut = b.point("knee_out_front", Point2(2 * xCr - kneeIn.x(), yK));
  const Polyline inseamF =
      joined(curve({{bF, std::nullopt}, {kneeIn, (hemIn - kneeIn).normalized()}}, kSideCurveCount),
             Polyline{hemIn});
  // 7. CF and crotch curve.
  const Point2 cfw = b.point("waist_cf", Point2(w - 0.5, 0));
  const Line bc = *Line::through(bF, c);
  const Point2 f = projectOntoLine(a, bc);
  const Point2 a1 = b.point("crotch_guide_front", a + 2.0 / 3.0 * (f - a));
  b.construction("crotch_guide_front_line", a, f);
  const Point2 uIn = (kneeIn - bF).normalized();
  const Polyline crotchF =
      curve({{c, Point2(0, 1)}, {a1, std::nullopt}, {bF, perpPlusX(uIn)}}, kCrotchCount);
  // 6 + 8. Side and waist; side-in reduced when the waist needs more room.
  const double targetF = (W + eW) / 4 + 1, targetB = (W + eW) / 4 - 1;
  auto frontSide = [&](double sIn) {
    const Point2 sw(sIn, -1.1);
    return joined(curve({{sw, std::nullopt},
                         {Point2(0, hl), Point2(0, 1)},
                         {kneeOut, (hemOut - kneeOut).normalized()}},
                        2 * kSideCurveCount),
                  Polyline{hemOut});
  };
  auto frontWaist = [&](const Polyline& side) {
    const Point2 cfDir = (c - cfw).normalized();
    return curve({{side.front(), perpPlusX(side[1] - side[0])}, {cfw, perpPlusX(cfDir)}},
                 kFineCurveCount);
  };
  double sIn = 2;
  for (int i = 0; i < 4; ++i) {
    const double excess = polylineLength(frontWaist(frontSide(sIn))) - targetF;
    if (excess >= 1.0)
      break;
    sIn -= 1.0 - excess + 0.05;
  }
  b.require(sIn > -4, "waist_circ + ease_waist is too large for the hip of the trouser block");
  const Polyline sideF = frontSide(sIn);
  const Point2 sw = b.point("waist_side_front", sideF.front());
  const Polyline waistFFine = frontWaist(sideF);
  const double excessF = polylineLength(waistFFine) - targetF;
  b.require(excessF >= 0.9, "the front waist has no room for its darts");
  const double d1 = excessF / 2;
  auto arcAt = [](const Polyline& pl, double x) {
    auto hit = firstIntersection(pl, Line::vertical(x));
    return hit ? hit->sA : polylineLength(pl) / 2;
  };
  const double x2 = ((xCr - d1 / 2) + sw.x()) / 2;
  const double depthF = std::min(9.0, 0.6 * hl);
  auto waistF = openDarts(waistFFine, {{"front_side", arcAt(waistFFine, x2), d1, depthF},
                                       {"front_crease", arcAt(waistFFine, xCr), d1, depthF}});
  if (!waistF)
    b.refuse("the front waist darts do not fit");

  // 9-13. Back.
  const Point2 w2 = b.point("cb_waist_guide", Point2(w - 1.25, 0));
  const Point2 up = (w2 - a).normalized();
  const Point2 rp = b.point("waist_cb", w2 + 2 * up);
  const Point2 hB = *intersectLines(*Line::through(a, w2), Line::horizontal(hl));
  const Point2 h1 = b.point("crotch_seam_back_top", hB + 2 * up);
  b.construction("cb_seam_line", a, rp);
  const Point2 kneeInB = b.point("knee_in_back", kneeIn + Point2(1, 0));
  const Point2 kneeOutB = b.point("knee_out_back", kneeOut - Point2(1, 0));
  const Point2 hemInB = b.point("hem_in_back", hemIn + Point2(1, 0));
  const Point2 hemOutB = b.point("hem_out_back", hemOut - Point2(1, 0));
  const double ext = 0.68 * q;
  auto backInseam = [&](double drop) {
    const Point2 b1(bF.x() + ext, br + drop);
    return joined(
        curve({{b1, std::nullopt}, {kneeInB, (hemInB - kneeInB).normalized()}}, kSideCurveCount),
        Polyline{hemInB});
  };
  const double inF = polylineLength(inseamF);
  const auto drop = bisect([&](double d) { return polylineLength(backInseam(d)) - inF; }, -4, 4);
  if (!drop)
    b.refuse("no back crotch point makes the inseams equal");
  const Polyline inseamB = backInseam(*drop);
  const Point2 b1 = b.point("crotch_point_back", inseamB.front());
  const Line b1h1 = *Line::through(b1, h1);
  const Point2 fB = projectOntoLine(a, b1h1);
  const Point2 a1B = b.point("crotch_guide_back", a + 2.0 / 3.0 * (fB - a));
  const Point2 uInB = (kneeInB - b1).normalized();
  const Polyline crotchB =
      curve({{h1, -up}, {a1B, std::nullopt}, {b1, perpPlusX(uInB)}}, kCrotchCount);
  // Back side at the hip: (H + ease)/4 from the crotch seam, horizontally on the hip line.
  const Polyline cbSeam = joined(Polyline{rp}, crotchB);
  const auto hipHit = firstIntersection(cbSeam, Line::horizontal(hl));
  if (!hipHit)
    b.refuse("the back crotch seam does not reach the hip line");
  const double xHb = hipHit->point.x() - w;
  const Point2 hipSideB = b.point("hip_side_back", Point2(xHb, hl));
  const double sideLenF = polylineLength(sideF);
  auto backSide = [&](double raise, double sInB) {
    const Point2 swB(xHb + sInB, -raise);
    return joined(curve({{swB, std::nullopt},
                         {hipSideB, Point2(0, 1)},
                         {kneeOutB, (hemOutB - kneeOutB).normalized()}},
                        2 * kSideCurveCount),
                  Polyline{hemOutB});
  };
  auto backWaist = [&](const Polyline& side) {
    return curve({{side.front(), perpPlusX(side[1] - side[0])}, {rp, perpPlusX(up)}},
                 kFineCurveCount);
  };
  double sInB = 2;
  Polyline sideB;
  for (int i = 0; i < 4; ++i) {
    const auto raise =
        bisect([&](double r) { return polylineLength(backSide(r, sInB)) - sideLenF; }, -4, 8);
    if (!raise)
      b.refuse("no back side-waist height makes the outseams equal");
    sideB = backSide(*raise, sInB);
    const double excess = polylineLength(backWaist(sideB)) - targetB;
    if (excess >= 1.0)
      break;
    sInB -= 1.0 - excess + 0.05;
  }
  const Point2 swB = b.point("waist_side_back", sideB.front());
  const Polyline waistBFine = backWaist(sideB);
  const double excessB = polylineLength(waistBFine) - targetB;
  b.require(excessB >= 0.9, "the back waist has no room for its darts");
  const double lenWB = polylineLength(waistBFine);
  auto waistB =
      openDarts(waistBFine, {{"back_side", lenWB / 3, excessB / 2, std::min(9.5, 0.55 * hl)},
                             {"back_cb", 2 * lenWB / 3, excessB / 2, std::min(11.0, 0.65 * hl)}});
  if (!waistB)
    b.refuse("the back waist darts do not fit");

  // Contours.
  b.contour("front_waist", waistF->points);
  b.contour("front_side", sideF);
  b.contour("front_cf", Polyline{cfw, c});
  b.contour("front_crotch", crotchF);
  b.contour("front_inseam", inseamF);
  b.contour("front_hem", Polyline{hemOut, hemIn});
  b.contour("back_waist", waistB->points);
  b.contour("back_side", sideB);
  b.contour("back_cb", Polyline{rp, h1});
  b.contour("back_crotch", crotchB);
  b.contour("back_inseam", inseamB);
  b.contour("back_hem", Polyline{hemOutB, hemInB});

  // Panels.
  Pattern& p = b.pattern();
  Polyline of;
  append(of, waistF->points);
  append(of, crotchF);  // starts at c: cfw -> c is the straight CF
  append(of, inseamF);
  append(of, reversed(sideF));
  Panel pf = makePanel("pants_front", of);
  pf.darts = waistF->darts;
  pf.grainline = grainline(Point2(xCr, 2), Point2(xCr, tl - 2));
  pf.cutCount = 2;
  pf.notches.push_back(Notch{"knee_in", kneeIn});
  pf.notches.push_back(Notch{"knee_out", kneeOut});
  Polyline ob;
  append(ob, waistB->points);
  append(ob, crotchB);
  append(ob, inseamB);
  append(ob, reversed(sideB));
  Panel pb = makePanel("pants_back", ob);
  pb.darts = waistB->darts;
  pb.grainline = grainline(Point2(xCr, 2), Point2(xCr, tl - 2));
  pb.cutCount = 2;
  pb.notches.push_back(Notch{"knee_in", kneeInB});
  pb.notches.push_back(Notch{"knee_out", kneeOutB});
  addPanelWithRegion(p, pf);
  addPanelWithRegion(p, pb);
  // The back is drawn on a trace of the front (not mirrored), so both outlines run the same
  // way along these seams.
  addSeam(p, "outseam", "pants_front", sw, hemOut, "pants_back", swB, hemOutB, 0, true);
  addSeam(p, "inseam", "pants_front", bF, hemIn, "pants_back", b1, hemInB, 0, true);
  // The crotch seams join each piece to its mirrored twin (left and right leg).
  p.seams.push_back(SeamPair{"centre_front", shortEdge(pf, cfw, bF), shortEdge(pf, cfw, bF), 0});
  p.seams.push_back(SeamPair{"centre_back", shortEdge(pb, rp, b1), shortEdge(pb, rp, b1), 0});
  b.point("hip_side_front", Point2(0, hl));
}

}  // namespace garmcap::drafts::detail
