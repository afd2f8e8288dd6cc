// One-piece dress (research/drafting_blocks.md §3: bodice + skirt joined by a waist seam, seed
// table 5.1 inputs), the woven blouse (§6.2 "Bunka blouse") and the high-waist skirt (§2.3).
#include <algorithm>
#include <cmath>
#include <limits>

#include "recipe_blocks.h"
#include "recipe_list.h"

namespace garmcap::drafts::detail {
namespace {

SleeveOptions sleeveFor(DraftBuilder& b, const BodiceDraft& d, double capFactor) {
  SleeveOptions o;
  o.fah = d.fah;
  o.bah = d.bah;
  o.capHeight = bunkaCapHeight(d, capFactor);
  o.capEase = b.design("sleeve_cap_ease");
  o.armLength = b.measurement("arm_shoulder_tip_to_wrist");
  o.lengthFactor = b.design("sleeve_length");
  o.wristOpening = b.measurement("arm_wrist_circ") + b.design("ease_wrist");
  o.origin = Point2(d.bw + 6 + d.fah, d.yS - o.capHeight);
  return o;
}

void addSleeveTo(DraftBuilder& b, const BodiceDraft& d, double capFactor,
                 const std::string& back = "bodice_back",
                 const std::string& front = "bodice_front") {
  if (b.design("sleeve_length") <= 0)
    return;  // sleeveless
  const SleeveDraft s = draftSleeve(b, sleeveFor(b, d, capFactor));
  addSleevePanel(b, s, back, d.spB, d.side, front, d.spF, d.side);
}

// The dress's skirt under the bodice `d`: the hip from the body, the waist the bodice's sewn
// waist, and the bodice's waist darts taken dart to dart.
SkirtOptions dressSkirt(const DraftBuilder& b, const BodiceDraft& d) {
  SkirtOptions s;
  const double half = (b.measurement("hip_circ") + b.design("ease_hip")) / 2;
  s.cbX = 0;
  s.cfX = d.bw;
  s.waistY = d.wbl;
  s.hipLength = b.measurement("waist_to_hip_b");
  s.length = b.design("skirt_length");
  s.hipBack = half / 2 - 1;
  s.hipFront = half / 2 + 1;
  s.waistBack = bodiceWaistBack(d);
  s.waistFront = bodiceWaistFront(d);
  s.hemFlare = b.design("hem_flare");
  // Skirt darts meet the bodice darts at the waist seam (back e and d, front b and a): the same
  // intakes at the same lengths along the seam, so each pair runs on through it.
  s.backDartX = std::vector<double>{d.backDarts[0].x, d.backDarts[1].x};
  s.frontDartX = std::vector<double>{d.frontDarts[0].x, d.frontDarts[1].x};
  s.backDartsAbove.emplace();
  for (const auto& x : d.backDarts)
    s.backDartsAbove->push_back({x.x - d.cbWaist.x(), x.width});
  s.frontDartsAbove.emplace();
  for (const auto& x : d.frontDarts)
    s.frontDartsAbove->push_back({x.x - d.sideWaistFront.x(), x.width});
  return s;
}

// Bunka's bodice darts often take in more than the skirt over the hip needs (a bust much
// larger than the hip): a skirt taking them would be wider at the side waist than at the hip,
// its side seam running out above the hip. The excess goes from the bodice darts into the
// bodice side seam instead (BodiceOptions::sideIntakeExtra), just enough for the skirt's side
// intake to be `minSide` (the design parameter skirt_side_intake): every skirt side seam then
// comes in from the hip to the waist by at least that much, and the darts still meet dart to
// dart. Every skirt block of research/drafting_blocks.md §2.1 takes part of the waist-hip
// difference at the side seam, none puts it all in the darts (Bunka [S9] a third of the front's
// suppression on each piece, Gilewska [S1] (d - 1)/4 and Donnanno [S1] about d/4 of d = (H -
// W)/2, Aldrich [S2] (H - W)/4 - 2.5, Keiko [S7] 3 cm): a skirt whose side runs straight from the
// hip to the waist has its whole hip curve in the darts. The bodice's side seam is a straight line
// from the underarm point, so the change tapers from nothing at the bust level to all of it at
// the waist; the bodice block keeps its bust (its half width solves for the dart openings at
// the bust level with the reduced darts). Solved by the secant method on trial bodices drawn
// into a scratch pattern.
double dressSideIntakeExtra(const DraftBuilder& b, const BodiceOptions& o, double minSide) {
  const double B = b.measurement("bust_circ"), W = b.measurement("waist_circ");
  const double wbl = b.measurement("neck_back_to_waist_b");
  auto skirtSide = [&](double extra) -> std::optional<double> {
    Pattern scratch;
    DraftBuilder sb(scratch, b.recipe());
    BodiceOptions t = o;
    t.sideIntakeExtra = extra;
    const auto fit = fitSkirtSide(dressSkirt(b, draftBodiceBlock(sb, B, W, wbl, t)));
    return fit ? std::optional(fit->sideIntake) : std::nullopt;
  };
  const auto s0 = skirtSide(0);
  if (!s0 || *s0 >= minSide)
    return 0;  // no excess (or no skirt at all: draftSkirt says why)
  // A trial whose bodice the block refuses (its waist darts would keep less than 30 % of their
  // width, draftBodiceBlock) counts as a skirt side that comes in too far: where the darts
  // cannot give the whole of minSide the solve stops at the most they can give (the skirt side
  // then comes in less, still more than with a floor of zero).
  auto residual = [&](double extra) -> std::optional<double> {
    try {
      const auto s = skirtSide(extra);
      return s ? std::optional(*s - minSide) : std::nullopt;
    } catch (const DraftError&) {
      return std::numeric_limits<double>::infinity();
    }
  };
  // Secant steps, and bisection once a trial has come in too far and the secant leaves the
  // bracket. Each cm moved adds about half a cm to the skirt's side intake (back and front
  // share it).
  double lo = 0, hi = 0;
  bool bracketed = false;
  double x0 = 0, f0 = *s0 - minSide, x1 = -2 * f0;
  for (int it = 0; it < 60; ++it) {
    const auto r1 = residual(x1);
    if (!r1)
      return x1;  // draftSkirt refuses with its own message
    if (std::abs(*r1) < 1e-6)
      return *r1 < 0 ? x1 + 1e-5 : x1;
    if (*r1 < 0) {
      lo = x1;
    } else {
      hi = x1;
      bracketed = true;
    }
    if (bracketed && hi - lo < 1e-6)
      return lo;  // the most the bodice darts can give
    double x2 = std::isfinite(*r1) && std::abs(*r1 - f0) > 1e-12 ? x1 - *r1 * (x1 - x0) / (*r1 - f0)
                                                                 : x1 - 2 * *r1;
    if (bracketed && !(x2 > lo && x2 < hi))
      x2 = (lo + hi) / 2;
    x0 = x1;
    f0 = *r1;
    x1 = x2;
  }
  return lo;
}

}  // namespace

void recipeDress(DraftBuilder& b) {
  BodiceOptions o;
  o.easeBust = b.design("ease_bust");
  o.easeWaist = b.design("ease_waist");
  o.bustpointToBustpoint = b.measurement("bustpoint_to_bustpoint");
  o.shoulderTipToTip = b.measurement("shoulder_tip_to_shoulder_tip_b");
  o.sideIntakeExtra = dressSideIntakeExtra(b, o, b.design("skirt_side_intake"));
  const BodiceDraft d = draftBodiceBlock(b, b.measurement("bust_circ"), b.measurement("waist_circ"),
                                         b.measurement("neck_back_to_waist_b"), o);
  addBodicePanels(b, d);
  const SkirtOptions s = dressSkirt(b, d);
  const SkirtDraft sk = draftSkirt(b, s);
  Pattern& p = b.pattern();
  addSeam(p, "waist_back", "bodice_back", d.cbWaist, d.sideWaistBack, "skirt_back", sk.cbWaist,
          sk.sideWaistBack);
  addSeam(p, "waist_front", "bodice_front", d.sideWaistFront, d.cfWaist, "skirt_front",
          sk.sideWaistFront, sk.cfWaist);
  // Where bodice and skirt meet: one notch halfway along each waist seam, at the same sewn
  // distance on both pieces (the darts between meet dart to dart).
  addSeamNotches(p, "waist_back", "waist_seam", 0.5);
  addSeamNotches(p, "waist_front", "waist_seam", 0.5);
  addSleeveTo(b, d, 1.0);
}

namespace {

// A bodice block without waist darts carried on below the waist to a hem, as one back and one
// front piece (the blouse and the shift dress). The side seam runs from the underarm point
// through `sideBack` / `sideFront` (waist, hip, hem side points); fish-eye darts of `dart` cm
// (none when 0) take part of the waist suppression, front under the bust point, back at the
// back-width line. `hemBack` runs CB hem -> side, `hemFront` side -> CF hem.
struct LongBodice {
  std::string backName, frontName;          // panel ids
  std::string sideBackName, sideFrontName;  // draft contours of the side seams
  Polyline sideBack, sideFront;             // waist side point ... hem side point
  Polyline hemBack, hemFront;
  double yHem = 0, dart = 0, lowApex = 0;
};

void addLongBodicePanels(DraftBuilder& b, const BodiceDraft& d, const LongBodice& l) {
  const Point2 cbHem = l.hemBack.front(), cfHem = l.hemFront.back();
  const Point2 hemB = l.sideBack.back(), hemF = l.sideFront.back();
  auto fishEye = [&](const std::string& name, double x, double topY) {
    DraftLine line{"dart:" + name,
                   Polyline{Point2(x, topY), Point2(x + l.dart / 2, d.wbl), Point2(x, l.lowApex),
                            Point2(x - l.dart / 2, d.wbl), Point2(x, topY)},
                   false};
    b.contour("dart_" + name, line.points);
    return line;
  };
  std::vector<DraftLine> backDarts, frontDarts;
  if (l.dart > 0) {
    // The back dart stops at the bust level so that the bust keeps all of ease_bust.
    backDarts.push_back(fishEye("back_waist", d.backDarts[1].x, d.yS));
    frontDarts.push_back(fishEye("front_waist", d.bp.x(), std::max(d.bp.y() + 2.5, d.yS)));
  }
  Polyline sideB{d.side}, sideF{d.side};
  append(sideB, l.sideBack);
  append(sideF, l.sideFront);
  b.contour(l.sideBackName, sideB);
  b.contour(l.sideFrontName, sideF);
  b.contour("hem_back", l.hemBack);
  b.contour("hem_front", l.hemFront);
  b.contour("centre_back", Polyline{d.cbNeck, cbHem});
  b.contour("centre_front", Polyline{d.fnp, cfHem});

  Pattern& p = b.pattern();
  Polyline back;
  append(back, d.backNeck);
  append(back, Polyline{d.shoulderDart.leg1, d.shoulderDart.apex, d.shoulderDart.leg2, d.spB});
  append(back, d.backArmhole);
  append(back, l.sideBack);
  append(back, reversed(l.hemBack));
  Panel pb = makePanel(l.backName, back);
  pb.darts.push_back(d.shoulderDart);
  for (const auto& dl : backDarts)
    pb.internalLines.push_back(dl);
  pb.grainline = grainline(Point2(4, 4), Point2(4, l.yHem - 3));
  pb.cutOnFold = true;
  addDoubleNotch(pb, "armhole_back", d.backArmhole, polylineLength(d.backArmhole) - 8);
  Polyline front = frontAboveSide(d);
  append(front, l.sideFront);
  append(front, l.hemFront);
  Panel pf = makePanel(l.frontName, front);
  pf.darts.push_back(Dart{"bust", d.bp, d.g2, d.g});
  for (const auto& dl : frontDarts)
    pf.internalLines.push_back(dl);
  pf.grainline = grainline(Point2(d.bw - 4, d.fnp.y() + 3), Point2(d.bw - 4, l.yHem - 3));
  pf.cutOnFold = true;
  pf.notches.push_back(Notch{
      "armhole_front", pointAlong(d.frontArmholeLower, polylineLength(d.frontArmholeLower) - 7)});
  addPanelWithRegion(p, pb);
  addPanelWithRegion(p, pf);
  addSeam(p, "shoulder", l.backName, d.snpB, d.spB, l.frontName, d.snpF, d.spF);
  addSeam(p, "side", l.backName, d.side, hemB, l.frontName, d.side, hemF);
}

}  // namespace

void recipeBlouse(DraftBuilder& b) {
  BodiceOptions o;
  o.easeBust = b.design("ease_bust");
  o.easeWaist = b.design("ease_waist");
  o.bustpointToBustpoint = b.measurement("bustpoint_to_bustpoint");
  o.bustpointToNeckSide = b.measurement("bustpoint_to_neck_side");
  o.underarmDrop = b.design("underarm_drop");
  o.waistDarts = false;
  const double B = b.measurement("bust_circ"), W = b.measurement("waist_circ");
  const double H = b.measurement("hip_circ"), hl = b.measurement("waist_to_hip_b");
  const BodiceDraft d = draftBodiceBlock(b, B, W, b.measurement("neck_back_to_waist_b"), o);
  const double wbl = d.wbl, yHem = wbl + b.design("blouse_length"), yHip = wbl + hl;
  b.point("level_hip", Point2(0, yHip));
  b.construction("hip_line", Point2(0, yHip), Point2(d.bw, yHip));
  b.construction("hem_line", Point2(0, yHem), Point2(d.bw, yHem));
  b.construction("centre_back_extension", Point2(0, wbl), Point2(0, yHem));
  // Waist shaping: half the suppression at the side, a quarter in each fish-eye dart (front
  // under the bust point, back at the back-width line), darts at least 0.2 cm.
  const double dTot = d.bw - (W + o.easeWaist) / 2;
  const double dart = std::max(0.25 * dTot, 0.2);
  const double cw = (dTot - 2 * dart) / 2;  // per side seam edge (negative: flares out)
  const double delta = ((H + b.design("ease_hip")) / 2 - d.bw) / 2;
  const Point2 wsB = b.point("waist_side_back_blouse", Point2(d.side.x() - cw, wbl));
  const Point2 wsF = b.point("waist_side_front_blouse", Point2(d.side.x() + cw, wbl));
  const Point2 hipB(d.side.x() + delta, yHip), hipF(d.side.x() - delta, yHip);
  b.point("hip_side_back", hipB);
  b.point("hip_side_front", hipF);
  // The hem side point lies on the waist -> hip line (extended below the hip), so the hip
  // girth is kept whatever the blouse length.
  auto onSide = [&](const Point2& w, const Point2& h) {
    return Point2(pointAtFraction(w, h, (yHem - wbl) / (yHip - wbl)));
  };
  const Point2 hemB = b.point("hem_side_back", onSide(wsB, hipB));
  const Point2 hemF = b.point("hem_side_front", onSide(wsF, hipF));
  const Point2 cbHem = b.point("hem_cb", Point2(0, yHem));
  const Point2 cfHem = b.point("hem_cf", Point2(d.bw, yHem));
  b.require(yHem > wbl + 3, "blouse_length must reach at least 3 cm below the waist");
  LongBodice l;
  l.backName = "bodice_back";
  l.frontName = "bodice_front";
  l.sideBackName = "side_back_blouse";
  l.sideFrontName = "side_front_blouse";
  l.sideBack = Polyline{wsB, hemB};
  l.sideFront = Polyline{wsF, hemF};
  l.hemBack = Polyline{cbHem, hemB};
  l.hemFront = Polyline{hemF, cfHem};
  l.yHem = yHem;
  l.dart = dart;
  l.lowApex = wbl + std::min(0.6 * hl, yHem - wbl - 2);
  addLongBodicePanels(b, d, l);
  addSleeveTo(b, d, 0.85);
}

// Shift dress (research/drafting_blocks.md §1.1 bodice, §2.2 flare): one back and one front
// piece from the shoulder to the hem, no waist seam and no waist darts in the bodice block; the
// waist is shaped (or not) at the side seam and by fish-eye darts only where the garment takes
// in at least 1 cm there. The side runs underarm -> waist -> hip, then turns about the hip
// point by the hem flare, as the A-line skirt's does, so the hip girth is kept. It drafts the
// dresses the darted one-piece dress cannot: a garment whose waist is about as wide as its bust.
void recipeDressShift(DraftBuilder& b) {
  BodiceOptions o;
  o.easeBust = b.design("ease_bust");
  o.easeWaist = b.design("ease_waist");
  o.bustpointToBustpoint = b.measurement("bustpoint_to_bustpoint");
  o.shoulderTipToTip = b.measurement("shoulder_tip_to_shoulder_tip_b");
  o.waistDarts = false;
  const double B = b.measurement("bust_circ"), W = b.measurement("waist_circ");
  const double H = b.measurement("hip_circ"), hl = b.measurement("waist_to_hip_b");
  const BodiceDraft d = draftBodiceBlock(b, B, W, b.measurement("neck_back_to_waist_b"), o);
  const double wbl = d.wbl, yHip = wbl + hl, yHem = wbl + b.design("skirt_length");
  b.require(yHem >= yHip + 5, "skirt_length = " + std::to_string(b.design("skirt_length")) +
                                  " cm ends above the hip (waist_to_hip_b + 5 cm): a dress that "
                                  "short is drafted as a top");
  b.point("level_hip", Point2(0, yHip));
  b.construction("hip_line", Point2(0, yHip), Point2(d.bw, yHip));
  b.construction("hem_line", Point2(0, yHem), Point2(d.bw, yHem));
  b.construction("centre_back_extension", Point2(0, wbl), Point2(0, yHem));
  // Waist: a quarter of the suppression in each fish-eye dart when that is at least 0.5 cm,
  // the rest at the side (negative: the side stands out at the waist).
  const double dTot = d.bw - (W + o.easeWaist) / 2;
  const double dart = 0.25 * dTot >= 0.5 ? 0.25 * dTot : 0.0;
  const double cw = (dTot - 2 * dart) / 2;
  const double delta = ((H + b.design("ease_hip")) / 2 - d.bw) / 2;
  const Point2 wsB = b.point("waist_side_back", Point2(d.side.x() - cw, wbl));
  const Point2 wsF = b.point("waist_side_front", Point2(d.side.x() + cw, wbl));
  const Point2 hipB = b.point("hip_side_back", Point2(d.side.x() + delta, yHip));
  const Point2 hipF = b.point("hip_side_front", Point2(d.side.x() - delta, yHip));
  // Each piece keeps at least 2 cm of width at the hip (a hip far under the bust would move the
  // side seam past CB or CF).
  b.require(hipB.x() > 2 && hipF.x() < d.bw - 2,
            "hip_circ + ease_hip = " + std::to_string(H + b.design("ease_hip")) +
                " cm is too small for the bodice's bust (" + std::to_string(2 * d.bw) +
                " cm) for a shift dress");
  const double theta = radToDeg(std::atan2(b.design("hem_flare"), yHem - yHip));
  const Point2 hemB = b.point("hem_side_back", rotateAbout(Point2(hipB.x(), yHem), hipB, -theta));
  const Point2 hemF = b.point("hem_side_front", rotateAbout(Point2(hipF.x(), yHem), hipF, theta));
  const Point2 cbHem = b.point("hem_cb", Point2(0, yHem));
  const Point2 cfHem = b.point("hem_cf", Point2(d.bw, yHem));
  // The hem meets CB and CF square and each side seam square (a flared hem curves up at the
  // side, as the A-line skirt's).
  const Point2 dB = (hemB - hipB).normalized(), dF = (hemF - hipF).normalized();
  LongBodice l;
  l.backName = "body_back";
  l.frontName = "body_front";
  l.sideBackName = "side_back";
  l.sideFrontName = "side_front";
  l.sideBack = Polyline{wsB, hipB, hemB};
  l.sideFront = Polyline{wsF, hipF, hemF};
  l.hemBack = curve({{cbHem, Point2(1, 0)}, {hemB, Point2(dB.y(), -dB.x())}}, kHemCount);
  l.hemFront = curve({{hemF, Point2(dF.y(), -dF.x())}, {cfHem, Point2(1, 0)}}, kHemCount);
  l.yHem = yHem;
  l.dart = dart;
  l.lowApex = wbl + 0.6 * hl;
  addLongBodicePanels(b, d, l);
  addSleeveTo(b, d, 1.0, "body_back", "body_front");
}

void recipeSkirtHighWaist(DraftBuilder& b) {
  BodiceOptions bo;  // the bodice the skirt top follows (Bunka defaults)
  const double B = b.measurement("bust_circ"), W = b.measurement("waist_circ");
  const BodiceDraft d = draftBodiceBlock(b, B, W, b.measurement("neck_back_to_waist_b"), bo);
  for (auto& l : b.pattern().lines)
    l.construction = true;
  SkirtOptions s;
  const double half = (b.measurement("hip_circ") + b.design("ease_hip")) / 2;
  s.cbX = 0;
  s.cfX = d.bw;
  s.waistY = d.wbl;
  s.hipLength = b.measurement("waist_to_hip_b");
  s.length = b.design("skirt_length");
  s.hipBack = half / 2 - 1;
  s.hipFront = half / 2 + 1;
  const double quarterW = (W + b.design("ease_waist")) / 4;
  s.waistBack = quarterW - 1;
  s.waistFront = quarterW + 1;
  s.hemFlare = b.design("hem_flare");
  s.waistRaise = b.design("waist_raise");
  s.bodice = &d;
  s.backDartX = std::vector<double>{d.backDarts[0].x, d.backDarts[1].x};
  s.frontDartX = std::vector<double>{d.frontDarts[0].x, d.frontDarts[1].x};
  b.point("level_waist", Point2(0, d.wbl));
  draftSkirt(b, s);
}

}  // namespace garmcap::drafts::detail
