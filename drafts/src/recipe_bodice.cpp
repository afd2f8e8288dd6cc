// Bunka-style adult women's bodice block, research/drafting_blocks.md §1.1, step by step.
// Origin A = back neck point, x toward CF, y down. Ease is a design parameter: the book's
// +12 cm bust / +6 cm waist are the defaults; proportional constants keep using the body bust.
#include <algorithm>
#include <cmath>
#include <optional>

#include "recipe_blocks.h"

namespace garmcap::drafts::detail {
namespace {

Point2 dirDeg(double deg) {
  return unitAtAngle(deg);
}

}  // namespace

BodiceDraft draftBodiceBlock(DraftBuilder& b, double B, double W, double WBL,
                             const BodiceOptions& o) {
  BodiceDraft d;
  d.bust = B;
  d.waist = W;
  d.wbl = WBL;
  // Constants (§1.1).
  const double dBL = B / 12 + 13.7;
  // The back waist darts d and e reach above the bust line (apexes on the G-line and 2 cm
  // above it), so with the darts closed the garment is narrower there than the frame. The
  // half width is widened by those openings so the garment bust is exactly B + ease_bust
  // (a fixed point: the dart widths grow with the half width).
  // Bust point height (step 10b) does not depend on the half width, so it is found first.
  const double fRise0 = B / 5 + 8.3, nk0 = B / 24 + 3.4, chestW0 = B / 8 + 6.2;
  const double yTop0 = dBL - fRise0;
  double bpY = dBL;
  std::optional<double> bpYRequested;
  if (o.bustpointToNeckSide) {
    const double dx =
        o.bustpointToBustpoint ? nk0 - *o.bustpointToBustpoint / 2 : nk0 - chestW0 / 2 - 0.7;
    const double n2 = *o.bustpointToNeckSide * *o.bustpointToNeckSide - dx * dx;
    b.require(n2 > 0,
              "bustpoint_to_neck_side is shorter than the horizontal distance from the "
              "neck point to the bust point");
    bpYRequested = yTop0 + std::sqrt(n2);
    // Bunka's front rise (B/5 + 8.3) grows faster with the bust than published NP-BP values
    // (Donnanno's chart): the bust point is kept on or up to 3 cm above the bust line (the
    // bust dart then stays above the bust level, as in the block); the requested point is drawn as
    // `bust_point_requested`.
    bpY = std::clamp(*bpYRequested, dBL - 3.0, dBL);
  }
  // 19 (widths first). Waist darts, % of the total suppression dT (§1.1 table); the side dart
  // c takes sideIntakeExtra more, half of it from the back darts and half from the front ones
  // in proportion to their widths, so the total stays dT.
  struct DartWidths {
    double a = 0, b = 0, c = 0, d = 0, e = 0, f = 0;
  };
  const double extra = o.sideIntakeExtra;
  b.require(extra >= 0, "sideIntakeExtra must not be negative");
  auto dartWidths = [&](double dT) {
    const double back = (0.35 + 0.18) * dT, front = (0.14 + 0.15) * dT;
    const double kb = back > 0 ? 1 - extra / 2 / back : 1;
    const double kf = front > 0 ? 1 - extra / 2 / front : 1;
    return DartWidths{0.14 * dT * kf, 0.15 * dT * kf, 0.11 * dT + extra,
                      0.35 * dT * kb, 0.18 * dT * kb, 0.07 * dT};
  };
  double bustDartOpening = 0;
  if (o.waistDarts) {
    const double yBLc = dBL, yGc = (8 + dBL) / 2 + 0.5, yLevel = dBL + o.underarmDrop;
    for (int it = 0; it < 8; ++it) {
      const double bwI = (B + o.easeBust) / 2 + bustDartOpening;
      const DartWidths w = dartWidths(bwI - (W + o.easeWaist) / 2);
      auto open = [&](double width, double apexY) {
        return apexY < yLevel ? width * (yLevel - apexY) / (WBL - apexY) : 0.0;
      };
      bustDartOpening =
          open(w.d, yGc) + open(w.e, yBLc - 2) + open(w.a, bpY + 2.5) + open(w.b, yBLc);
    }
  }
  const double bw = (B + o.easeBust) / 2 + bustDartOpening;
  const double backW = B / 8 + 7.4;
  const double chestW = B / 8 + 6.2;
  const double fRise = B / 5 + 8.3;
  const double nk = B / 24 + 3.4;
  const double sDart = B / 32 - 0.8;
  const double thBust = B / 4 - 2.5;
  const double dTot = bw - (W + o.easeWaist) / 2;
  d.bw = bw;
  d.thBust = thBust;
  d.sDart = sDart;
  d.dTot = dTot;
  b.require(WBL > dBL + 5, "neck_back_to_waist_b = " + std::to_string(WBL) +
                               " cm is too short for bust_circ = " + std::to_string(B) +
                               " cm (the bust line would fall below the waist)");
  b.require(!o.waistDarts || dTot >= 1.0,
            "waist_circ + waist ease (" + std::to_string(W + o.easeWaist) +
                " cm) must stay at least 2 cm below bust_circ + bust ease (" +
                std::to_string(B + o.easeBust) + " cm) for a darted bodice");
  b.require(chestW + backW < bw - 1.0,
            "bust ease too small: back width + chest width exceed the half bust");

  // 1-2. Frame: CB line, waist line, CF line, bust line.
  const Point2 A = b.point("neck_back_cb", Point2(0, 0));
  const double yBL = dBL;
  d.yBL = yBL;
  b.point("level_bust", Point2(0, yBL + o.underarmDrop));
  b.point("level_waist", Point2(0, WBL));
  const Point2 waistCbGuide = b.point("waist_cb_guide", Point2(0, WBL));
  const Point2 cfWaist = b.point("waist_cf", Point2(bw, WBL));
  const Point2 bustCb = b.point("bust_cb", Point2(0, yBL));
  const Point2 bustCf = b.point("bust_cf", Point2(bw, yBL));
  b.construction("centre_back_guide", A, waistCbGuide);
  b.construction("waist_line", waistCbGuide, cfWaist);
  b.construction("bust_line", bustCb, bustCf);
  // 3. Front top point and line.
  const Point2 Bt = b.point("front_top_cf", Point2(bw, yBL - fRise));
  b.construction("centre_front", Bt, cfWaist);
  b.construction("front_top_line", Bt, Point2(bw - chestW, Bt.y()));
  // 4-5. Back width line, shoulder-dart guide line, E.
  const Point2 C = b.point("back_width_bust", Point2(backW, yBL));
  b.construction("back_width_line", Point2(backW, 0), C);
  b.construction("neck_line_back", A, Point2(backW, 0));
  const Point2 D = b.point("back_width_dart_level", Point2(backW, 8));
  b.construction("shoulder_dart_guide", Point2(0, 8), D);
  const Point2 E = b.point("shoulder_dart_apex", Point2(backW / 2 + 1, 8));
  // 6. G-line.
  const double yG = (8 + yBL) / 2 + 0.5;
  d.yG = yG;
  b.construction("g_line", Point2(backW, yG), Point2(bw, yG));
  // 7. Chest line.
  const double xCh = bw - chestW;
  b.construction("chest_line", Point2(xCh, Bt.y()), Point2(xCh, yBL));
  // 8. F and G.
  const Point2 F = b.point("armhole_front_bust", Point2(xCh - B / 32, yBL));
  const Point2 G = b.point("armhole_front_g", Point2(F.x(), yG));
  b.construction("front_armhole_guide", F, G);
  // 9. Side line and the armhole-guide unit.
  const double xS = (C.x() + F.x()) / 2;
  const double yS = yBL + o.underarmDrop;
  d.yS = yS;
  const Point2 S = b.point("bust_side", Point2(xS, yS));
  const double tri = (F.x() - C.x()) / 6;
  b.require(tri > 0.2, "bust ease too small: no room between back width and chest width");
  // 11. Front neckline.
  const Point2 snpF = b.point("neck_side_front", Point2(bw - nk, Bt.y()));
  const Point2 fnp = b.point("neck_front_cf", Point2(bw, Bt.y() + nk + 0.5));
  const Point2 K(snpF.x(), fnp.y());
  const Point2 nf = K + ((Bt - K).norm() / 3 - 0.5) * (Bt - K).normalized();
  b.point("neck_front_guide", nf);
  b.construction("neck_front_box", Polyline{snpF, K, fnp});
  d.frontNeck = curve({{snpF, Point2(std::sin(degToRad(22)), std::cos(degToRad(22)))},
                       {nf, std::nullopt},
                       {fnp, Point2(1, 0)}},
                      kNeckCount);
  // 12. Back neckline.
  const double nkB = nk + 0.2;
  const Point2 snpB = b.point("neck_side_back", Point2(nkB, -nkB / 3));
  const Point2 M(nkB / 3, 0);
  d.backNeck = curve({{A, Point2(1, 0)},
                      {M, Point2(1, 0)},
                      {snpB, Point2(std::sin(degToRad(18)), -std::cos(degToRad(18)))}},
                     kNeckCount);
  // 10. Bust point (10b: the dissertation's BPBP / NPBP override when given).
  Point2 bp(bw - chestW / 2 - 0.7, yBL);
  if (o.bustpointToBustpoint)
    bp.x() = bw - *o.bustpointToBustpoint / 2;
  bp.y() = bpY;
  if (bpYRequested)
    b.point("bust_point_requested", Point2(bp.x(), *bpYRequested));
  b.require(bp.y() > yG + 2 && bp.y() < yBL + 4,
            "bustpoint_to_neck_side = " + std::to_string(o.bustpointToNeckSide.value_or(0)) +
                " cm places the bust point " + std::to_string(bp.y() - yBL) +
                " cm from the bust line (allowed: between the armhole G-line and 4 cm below)");
  b.require(bp.x() > F.x() + 3 && bp.x() < bw - 3,
            "bustpoint_to_bustpoint places the bust point outside the front chest");
  b.point("bust_point", bp);
  d.bp = bp;
  // 13-14. Shoulders.
  const Point2 uF = dirDeg(180 - 22);  // toward the side, 22 deg below horizontal
  const Point2 uB = dirDeg(18);        // toward the side (+x), 18 deg below horizontal
  double lenF = (snpF.x() - xCh) / std::cos(degToRad(22)) + 1.8;
  double lenB = lenF + sDart;
  if (o.shoulderTipToTip) {
    // Dress (table 5.1): back shoulder tip on the 18-degree line at x = BiS/2.
    lenB = (*o.shoulderTipToTip / 2 - snpB.x()) / std::cos(degToRad(18));
    lenF = lenB - sDart;
  }
  const Point2 Q = snpB + ((E.x() - snpB.x()) / uB.x()) * uB;
  b.require(lenF > 6 && (Q - snpB).norm() + 1.5 + sDart + 2 < lenB,
            "shoulder_tip_to_shoulder_tip_b = " + std::to_string(o.shoulderTipToTip.value_or(0)) +
                " cm leaves no room for the shoulder and its dart");
  Point2 spF = snpF + lenF * uF;
  // 15. Back shoulder dart, trued: the outer leg is made as long as the inner one, then the
  // shoulder tip is placed so that back shoulder minus dart = front shoulder.
  const Point2 leg1 = Q + 1.5 * uB;
  Point2 leg2 = leg1 + sDart * uB;
  leg2 = E + (leg1 - E).norm() * (leg2 - E).normalized();
  Point2 spB = leg2 + (lenF - (leg1 - snpB).norm()) * uB;
  spB.y() -= o.shoulderRaise;
  spF.y() -= o.shoulderRaise;
  b.point("shoulder_tip_front", spF);
  b.point("shoulder_tip_back", spB);
  b.point("shoulder_dart_leg_neck", leg1);
  b.point("shoulder_dart_leg_tip", leg2);
  b.construction("shoulder_dart_guide_q", E, Q);
  b.require(spB.x() < C.x() + 4 && spB.x() > C.x() - 6 && spF.x() > F.x() - 4,
            "the shoulder tips fall too far from the armhole (shoulder_tip_to_shoulder_tip_b "
            "does not fit bust_circ)");
  d.shoulderDart = Dart{"back_shoulder", E, leg1, leg2};
  // 16. Bust dart (armhole dart), rotation that moves G up toward the shoulder.
  const Point2 g2 = b.point("bust_dart_upper", rotateAbout(G, bp, thBust));
  b.require(g2.y() < G.y(), "bust dart opens the wrong way");
  // 17. Back armhole.
  const Point2 Cs(backW, yS);
  const Point2 tb = b.point("armhole_back_touch", Point2(backW, yG));
  const Point2 gb = Cs + (tri + 0.8) * Point2(1, -1).normalized();
  b.point("armhole_back_guide", gb);
  d.backArmhole = curve({{spB, Point2(-std::sin(degToRad(18)), std::cos(degToRad(18)))},
                         {tb, Point2(0, 1)},
                         {gb, std::nullopt},
                         {S, Point2(1, 0)}},
                        kArmholeCount);
  // 18. Front armhole: upper part touches the chest line, lower part G -> guide -> S.
  const Point2 Fs(F.x(), yS);
  // The armhole touches the chest line; when a short shoulder (dress: BiS) ends inside the
  // chest line, touch 0.5 cm inside the shoulder tip instead so the curve stays concave.
  const double xTouch = std::max(xCh, std::max(spF.x(), g2.x()) + 0.5);
  const Point2 touchF = b.point("armhole_front_touch", Point2(xTouch, (spF.y() + g2.y()) / 2));
  const Point2 tG2 = rotateAbout(Point2(0, 1), Point2(0, 0), thBust);
  d.frontArmholeUpper = curve({{spF, Point2(std::sin(degToRad(22)), std::cos(degToRad(22)))},
                               {touchF, Point2(0, 1)},
                               {g2, tG2}},
                              kArmholeCount);
  const Point2 gf = Fs + (tri + 0.5) * Point2(-1, -1).normalized();
  b.point("armhole_front_guide", gf);
  d.frontArmholeLower =
      curve({{G, Point2(0, 1)}, {gf, std::nullopt}, {S, Point2(-1, 0)}}, kArmholeCount);
  // Armhole lengths with the bust dart closed (rotation keeps lengths).
  d.fah = polylineLength(d.frontArmholeUpper) + polylineLength(d.frontArmholeLower);
  d.bah = polylineLength(d.backArmhole);
  d.spFClosed = rotateAbout(spF, bp, -thBust);
  b.point("shoulder_tip_front_dart_closed", d.spFClosed);

  // 19. Waist darts, % of the total suppression.
  const DartWidths widths = dartWidths(dTot);
  // A garment wider at the waist than at the bust (a shift, no waist darts) has no darts to
  // lose; its dart specs then only place the fish-eye darts.
  b.require(dTot <= 0 || (widths.a > 0.3 * 0.14 * dTot && widths.e > 0.3 * 0.18 * dTot),
            "the side seam cannot take " + std::to_string(extra) +
                " cm more of the waist suppression (the waist darts would vanish)");
  const double a = widths.a, bb = widths.b, c = widths.c, dd = widths.d, e = widths.e, f = widths.f;
  d.dartC = c;
  d.dartF = f;
  d.cbWaist = b.point("waist_cb", Point2(f, WBL));
  d.cbBust = bustCb;
  d.sideWaistBack = b.point("waist_side_back", Point2(xS - c / 2, WBL));
  d.sideWaistFront = b.point("waist_side_front", Point2(xS + c / 2, WBL));
  d.backDarts = {{"back_waist_e", E.x() - 0.5, e, yBL - 2}, {"back_waist_d", C.x() - 1, dd, yG}};
  d.frontDarts = {{"front_waist_b", F.x() + 1.5, bb, yBL},
                  {"front_waist_a", bp.x(), a, bp.y() + 2.5}};
  b.construction("side_line", Point2(xS, yBL), Point2(xS, WBL));

  d.cbNeck = A;
  d.snpB = snpB;
  d.snpF = snpF;
  d.fnp = fnp;
  d.spB = spB;
  d.spF = spF;
  d.side = S;
  d.g = G;
  d.g2 = g2;
  d.cfWaist = cfWaist;
  // Contours.
  b.contour("neck_back", d.backNeck);
  b.contour("neck_front", d.frontNeck);
  b.contour("shoulder_back", Polyline{snpB, leg1, E, leg2, spB});
  b.contour("shoulder_front", Polyline{snpF, spF});
  b.contour("armhole_back", d.backArmhole);
  b.contour("armhole_front_upper", d.frontArmholeUpper);
  b.contour("bust_dart", Polyline{g2, bp, G});
  b.contour("armhole_front_lower", d.frontArmholeLower);
  return d;
}

namespace {

// Back and front waist seams with their darts: back from CB to the side, front from the side
// to CF (both left to right).
LineWithDarts waistWithDarts(DraftBuilder& b, const Point2& from, const Point2& to,
                             const std::vector<BodiceDraft::WaistDart>& darts) {
  std::vector<DartSpec> specs;
  for (const auto& d : darts)
    specs.push_back({d.name, d.x - from.x(), d.width, d.apexY});
  auto r = openDarts(Polyline{from, to}, specs);
  if (!r)
    b.refuse("the waist darts do not fit between centre and side (waist or bust ease)");
  return *r;
}

}  // namespace

Polyline frontAboveSide(const BodiceDraft& d) {
  Polyline front;
  append(front, d.fnp);
  append(front, reversed(d.frontNeck));
  append(front, d.spF);
  append(front, d.frontArmholeUpper);
  append(front, d.bp);
  append(front, d.frontArmholeLower);
  return front;
}

double bodiceWaistBack(const BodiceDraft& d) {
  double w = d.sideWaistBack.x() - d.cbWaist.x();
  for (const auto& x : d.backDarts)
    w -= x.width;
  return w;
}

double bodiceWaistFront(const BodiceDraft& d) {
  double w = d.cfWaist.x() - d.sideWaistFront.x();
  for (const auto& x : d.frontDarts)
    w -= x.width;
  return w;
}

void addBodicePanels(DraftBuilder& b, const BodiceDraft& d) {
  Pattern& p = b.pattern();
  // Back: A -> neck -> SNPb -> shoulder with dart -> SPb -> armhole -> S -> side -> waist (side
  // to CB, darts) -> CB waist -> CB at bust -> A.
  const auto backWaist = waistWithDarts(b, d.cbWaist, d.sideWaistBack, d.backDarts);
  Polyline back;
  append(back, d.backNeck);
  append(back, Polyline{d.shoulderDart.leg1, d.shoulderDart.apex, d.shoulderDart.leg2, d.spB});
  append(back, d.backArmhole);
  append(back, reversed(backWaist.points));
  append(back, d.cbBust);
  Panel pb = makePanel("bodice_back", back);
  pb.darts.push_back(d.shoulderDart);
  for (const auto& x : backWaist.darts)
    pb.darts.push_back(x);
  pb.grainline =
      grainline(Point2(d.cbBust.x() + 4, d.cbNeck.y() + 4), Point2(d.cbBust.x() + 4, d.wbl - 3));
  // Bunka's dart f takes 7 % of the waist suppression at the centre back, which leaves the
  // fold line (x 0 -> f at the waist): the back cannot be cut on the fold. It is cut twice
  // and its halves are sewn at the centre back (issue 18), like the skirt back under it.
  pb.cutCount = 2;
  pb.cutOnFold = false;
  addDoubleNotch(pb, "armhole_back", d.backArmhole, polylineLength(d.backArmhole) - 8);
  b.contour("waist_back", backWaist.points);
  b.contour("side_back", Polyline{d.side, d.sideWaistBack});
  b.contour("centre_back", Polyline{d.cbNeck, d.cbBust, d.cbWaist});

  const auto frontWaist = waistWithDarts(b, d.sideWaistFront, d.cfWaist, d.frontDarts);
  Polyline front = frontAboveSide(d);
  append(front, frontWaist.points);
  Panel pf = makePanel("bodice_front", front);
  pf.darts.push_back(Dart{"bust", d.bp, d.g2, d.g});
  for (const auto& x : frontWaist.darts)
    pf.darts.push_back(x);
  pf.grainline = grainline(Point2(d.bw - 4, d.fnp.y() + 3), Point2(d.bw - 4, d.wbl - 3));
  pf.cutCount = 1;
  pf.cutOnFold = true;
  pf.notches.push_back(Notch{
      "armhole_front", pointAlong(d.frontArmholeLower, polylineLength(d.frontArmholeLower) - 7)});
  b.contour("waist_front", frontWaist.points);
  b.contour("side_front", Polyline{d.side, d.sideWaistFront});
  b.contour("centre_front_line", Polyline{d.fnp, d.cfWaist});

  addPanelWithRegion(p, pb);
  addPanelWithRegion(p, pf);
  const Panel& backPanel = p.panel("bodice_back");
  p.seams.push_back(SeamPair{"bodice_centre_back", shortEdge(backPanel, d.cbWaist, d.cbNeck),
                             shortEdge(backPanel, d.cbWaist, d.cbNeck), 0});
  addSeam(p, "shoulder", "bodice_back", d.snpB, d.spB, "bodice_front", d.snpF, d.spF);
  addSeam(p, "side", "bodice_back", d.side, d.sideWaistBack, "bodice_front", d.side,
          d.sideWaistFront);
}

}  // namespace garmcap::drafts::detail
