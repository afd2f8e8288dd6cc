// Knit sweater (research/drafting_blocks.md §6.4: Teagan / Gill): no darts, zero or negative
// ease, front = back except the neckline, a low cap without cap ease. Widths and depths are
// the Bunka proportions of the bust (§1.1) so the knit block sits on the same body frame as
// the woven blocks. The back is drawn from CB (x = 0) to the side line; the front is its mirror
// image about the side line (CF at x = 2 x quarter), as drafts lay out front and back.
#include <cmath>

#include "recipe_blocks.h"
#include "recipe_list.h"

namespace garmcap::drafts::detail {

void recipeSweater(DraftBuilder& b) {
  const double B = b.measurement("bust_circ"), H = b.measurement("hip_circ");
  const double wbl = b.measurement("neck_back_to_waist_b"), hl = b.measurement("waist_to_hip_b");
  const double quarter = (B + b.design("ease_bust")) / 4;
  const double hipQuarter = (H + b.design("ease_hip")) / 4;
  const double yBL = B / 12 + 13.7 + b.design("armhole_drop");
  const double backW = B / 8 + 6.2;      // knit: the narrower Bunka chest width on both pieces
  const double nk = B / 24 + 3.4 + 0.5;  // knit neck 0.5 cm wider
  b.require(wbl > yBL + 4, "neck_back_to_waist_b too short for bust_circ (bust line below waist)");
  b.require(quarter > backW + 1.0,
            "ease_bust = " + std::to_string(b.design("ease_bust")) +
                " cm leaves no room for the armhole (too much negative ease)");
  const double yHem = wbl + b.design("sweater_length"), yHip = wbl + hl;
  b.require(yHem > yBL + 8, "sweater_length too short: the hem would meet the armhole");
  const double axis = quarter;  // side line = mirror axis
  auto mirror = [&](const Point2& p) { return Point2(2 * axis - p.x(), p.y()); };
  auto mirrorPl = [&](const Polyline& pl) {
    Polyline out;
    for (const auto& p : pl)
      out.push_back(mirror(p));
    return out;
  };
  // Frame.
  const Point2 A = b.point("neck_back_cb", Point2(0, 0));
  b.point("level_bust", Point2(0, yBL));
  b.point("level_waist", Point2(0, wbl));
  b.point("level_hip", Point2(0, yHip));
  b.construction("bust_line", Point2(0, yBL), Point2(2 * axis, yBL));
  b.construction("waist_line", Point2(0, wbl), Point2(2 * axis, wbl));
  b.construction("hip_line", Point2(0, yHip), Point2(2 * axis, yHip));
  b.construction("side_line", Point2(axis, yBL - 3), Point2(axis, std::max(yHem, yHip)));
  b.construction("back_width_line", Point2(backW, 0), Point2(backW, yBL));
  b.construction("front_width_line", mirror(Point2(backW, 0)), mirror(Point2(backW, yBL)));
  // Neck and shoulder (18 degrees, tip 0.5 cm past the width line).
  const Point2 snp = b.point("neck_side_back", Point2(nk + 0.2, -(nk + 0.2) / 3));
  const Point2 u = unitAtAngle(18);
  const Point2 sp = b.point("shoulder_tip_back", snp + ((backW + 0.5 - snp.x()) / u.x()) * u);
  b.require(sp.x() > snp.x() + 6, "the shoulder is too short for bust_circ");
  const Polyline backNeck = curve({{A, Point2(1, 0)},
                                   {Point2((nk + 0.2) / 3, 0), Point2(1, 0)},
                                   {snp, Point2(std::sin(degToRad(18)), -std::cos(degToRad(18)))}},
                                  kNeckCount);
  const double frontDepth = nk + 2.5;
  const Point2 fnp = b.point("neck_front_cf_back_frame", Point2(0, snp.y() + frontDepth));
  const Polyline frontNeckBackFrame =
      curve({{A + Point2(0, 0) + fnp - A, Point2(1, 0)},
             {Point2(snp.x() * 0.55, snp.y() + frontDepth * 0.75), std::nullopt},
             {snp, Point2(std::sin(degToRad(18)), -std::cos(degToRad(18)))}},
            kNeckCount);
  // Armhole: shoulder tip -> touch the width line -> corner guide -> underarm point.
  const double yG = (sp.y() + yBL) / 2 + 1;
  const Point2 touch = b.point("armhole_touch", Point2(backW, yG));
  const double tri = (quarter - backW) / 3;
  const Point2 guide = Point2(backW, yBL) + (tri + 0.5) * Point2(1, -1).normalized();
  const Point2 S = b.point("bust_side", Point2(axis, yBL));
  const Polyline armhole = curve({{sp, Point2(-std::sin(degToRad(18)), std::cos(degToRad(18)))},
                                  {touch, Point2(0, 1)},
                                  {guide, std::nullopt},
                                  {S, Point2(1, 0)}},
                                 kArmholeCount);
  // Side: straight from the underarm to the hip width, vertical below the hip; one middle
  // vertex always (at the hip, or half way when the hem is above the hip) so vertex counts do
  // not depend on the body.
  const Point2 hipSide(hipQuarter, yHip);
  Point2 mid, hem;
  if (yHem > yHip + 0.5) {
    mid = hipSide;
    hem = Point2(hipQuarter, yHem);
  } else {
    hem = pointAtFraction(S, hipSide, (yHem - yBL) / (yHip - yBL));
    mid = midpoint(S, hem);
  }
  b.require(hem.x() < axis + 12 && hem.x() > 2, "hip_circ does not fit bust_circ for a sweater");
  b.point("hem_side_back", hem);
  const Point2 cbHem = b.point("hem_cb", Point2(0, yHem));
  // Draft contours (back, and the front as the mirror image).
  b.contour("neck_back", backNeck);
  b.contour("shoulder_back", Polyline{snp, sp});
  b.contour("armhole_back", armhole);
  b.contour("side_back", Polyline{S, mid, hem});
  b.contour("hem_back", Polyline{cbHem, hem});
  b.contour("centre_back", Polyline{A, cbHem});
  b.contour("neck_front", mirrorPl(frontNeckBackFrame));
  b.contour("shoulder_front", mirrorPl(Polyline{snp, sp}));
  b.contour("armhole_front", mirrorPl(armhole));
  b.contour("side_front", mirrorPl(Polyline{S, mid, hem}));
  b.contour("hem_front", mirrorPl(Polyline{cbHem, hem}));
  b.contour("centre_front", mirrorPl(Polyline{fnp, cbHem}));
  b.point("neck_side_front", mirror(snp));
  b.point("shoulder_tip_front", mirror(sp));
  b.point("neck_front_cf", mirror(fnp));
  b.point("hem_cf", mirror(cbHem));
  b.point("hem_side_front", mirror(hem));

  Pattern& p = b.pattern();
  Polyline back;
  append(back, backNeck);
  append(back, sp);
  append(back, armhole);
  append(back, Polyline{mid, hem, cbHem});
  Panel pb = makePanel("body_back", back);
  pb.cutOnFold = true;
  pb.grainline = grainline(Point2(4, 3), Point2(4, yHem - 3));
  addDoubleNotch(pb, "armhole_back", armhole, polylineLength(armhole) - 8);
  Polyline front;
  append(front, frontNeckBackFrame);
  append(front, sp);
  append(front, armhole);
  append(front, Polyline{mid, hem, cbHem});
  Panel pf = makePanel("body_front", mirrorPl(front));
  pf.cutOnFold = true;
  pf.grainline = grainline(mirror(Point2(4, fnp.y() + 3)), mirror(Point2(4, yHem - 3)));
  pf.notches.push_back(
      Notch{"armhole_front", mirror(pointAlong(armhole, polylineLength(armhole) - 7))});
  addPanelWithRegion(p, pb);
  addPanelWithRegion(p, pf);
  addSeam(p, "shoulder", "body_back", snp, sp, "body_front", mirror(snp), mirror(sp));
  addSeam(p, "side", "body_back", S, hem, "body_front", mirror(S), mirror(hem));
  // Knit sleeve: a cap 25 % lower than the woven 5/6 rule (§6.4 says knits go down to about
  // half; 0.75 keeps the sleeve width near the upper arm plus ~15 %), no cap ease by default.
  if (b.design("sleeve_length") > 0) {
    SleeveOptions o;
    o.fah = o.bah = polylineLength(armhole);
    o.capHeight = 0.75 * (yBL - sp.y()) * 5.0 / 6.0;
    o.capEase = b.design("sleeve_cap_ease");
    o.armLength = b.measurement("arm_shoulder_tip_to_wrist");
    o.lengthFactor = b.design("sleeve_length");
    o.wristOpening = b.measurement("arm_wrist_circ") + b.design("ease_wrist");
    o.outFront = 1.2;
    o.outBack = 1.2;
    o.inFront = 0.6;
    o.inBack = 0.4;
    o.origin = Point2(2 * axis + 6 + o.fah, yBL - o.capHeight);
    const SleeveDraft s = draftSleeve(b, o);
    addSleevePanel(b, s, "body_back", sp, S, "body_front", mirror(sp), mirror(S));
  }
}

}  // namespace garmcap::drafts::detail
