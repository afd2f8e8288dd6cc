#pragma once
// The blocks the recipes are assembled from (research/drafting_blocks.md): the Bunka-style
// bodice (§1.1), the one-algorithm skirt (§2.1-2.3), the Bunka set-in sleeve (§4.1, cap fitted
// to the armhole as in §4.4), the Bunka-school trousers (§5.1) and the knit body (§6.4).

#include <optional>
#include <string>
#include <vector>

#include "recipe_common.h"

namespace garmcap::drafts::detail {

// ---- bodice ---------------------------------------------------------------------------------
struct BodiceOptions {
  double easeBust = 12;                        // Bunka: B/2 + 6 per half
  double easeWaist = 6;                        // Bunka: W/2 + 3 per half
  std::optional<double> bustpointToBustpoint;  // J01 override of the bust point (step 10b)
  std::optional<double> bustpointToNeckSide;   // J02
  std::optional<double> shoulderTipToTip;      // I07: back shoulder tip at x = BiS/2 (dress)
  double underarmDrop = 0;                     // blouse: underarm point lowered (cm)
  double shoulderRaise = 0;                    // blouse: shoulder tips raised (cm)
  bool waistDarts = true;  // false: the garment shapes the waist itself (no Dtot check)
  // Waist suppression (cm per half) moved from the waist darts into the side seam: half from
  // the back darts e and d, half from the front darts b and a, in proportion to their widths;
  // the side dart c grows by it. A dress whose skirt takes the bodice darts sets it so that the
  // skirt's side seam still comes in from the hip to the waist.
  double sideIntakeExtra = 0;
};

struct BodiceDraft {
  double bust = 0, waist = 0, wbl = 0;
  double bw = 0, yBL = 0, yG = 0, yS = 0, thBust = 0, sDart = 0, dTot = 0;
  Point2 cbNeck, snpB, snpF, fnp, spB, spF, spFClosed, side, g, g2, bp, cbWaist, cbBust;
  Point2 cfWaist, sideWaistBack, sideWaistFront;
  Polyline backNeck;           // cbNeck -> snpB
  Polyline frontNeck;          // snpF -> fnp
  Dart shoulderDart;           // leg1 (neck side), leg2 (shoulder side), apex
  Polyline backArmhole;        // spB -> side
  Polyline frontArmholeUpper;  // spF -> g2
  Polyline frontArmholeLower;  // g -> side
  double fah = 0, bah = 0;     // armhole lengths, bust dart closed
  // Waist darts as specs (centre x, width, apex y), so garments can reuse or reshape them.
  struct WaistDart {
    std::string name;
    double x = 0, width = 0, apexY = 0;
  };
  std::vector<WaistDart> backDarts, frontDarts;  // back: e, d (CB -> side); front: b, a
  double dartC = 0, dartF = 0;
};

BodiceDraft draftBodiceBlock(DraftBuilder& b, double bust, double waist, double wbl,
                             const BodiceOptions& o);

/// The front piece's outline from the CF neck point to the underarm point: neck, shoulder,
/// armhole with the bust dart open (legs at g2 and g, apex at the bust point).
Polyline frontAboveSide(const BodiceDraft& d);

/// Sewn waist length of the bodice back / front piece (darts closed).
double bodiceWaistBack(const BodiceDraft& d);
double bodiceWaistFront(const BodiceDraft& d);

/// Waist-length bodice panels (bodice_back, bodice_front; cut on the fold at CB/CF... see
/// docs) with shoulder and side seams.
void addBodicePanels(DraftBuilder& b, const BodiceDraft& d);

// ---- skirt ----------------------------------------------------------------------------------
struct SkirtOptions {
  double cbX = 0;                    // CB line
  double cfX = 0;                    // CF line (cfX - cbX = half hip with ease for a skirt alone)
  double waistY = 0;                 // waist line
  double hipLength = 18;             // waist -> hip
  double length = 60;                // waist -> hem at CF
  double hipBack = 0, hipFront = 0;  // widths at the hip line, from CB / CF
  double waistBack = 0, waistFront = 0;  // sewn waist per piece (without darts)
  double sideRaise = 1.2, cbDrop = 1.0;
  double hemFlare = 0;    // cm added at the hem per side seam edge (negative: tapered)
  double waistRaise = 0;  // high-waist: top edge this far above the waist line
  std::optional<std::vector<double>> backDartX, frontDartX;  // dart centres (high waist)
  // Darts of the piece sewn above at the waist seam (a dress's bodice), which the skirt's darts
  // must meet: per dart its centre's length along the waist from the seam's start (back: from
  // CB, front: from the side) and its intake. Given both, the skirt takes these darts and
  // solves its side intake and the side line's place at the hip so that its waist keeps
  // waistBack / waistFront sewn.
  struct MatchedDart {
    double centreS = 0, width = 0;
  };
  std::optional<std::vector<MatchedDart>> backDartsAbove, frontDartsAbove;
  const BodiceDraft* bodice = nullptr;  // high waist: lines above the waist follow it
  std::string prefix = "skirt";
};

struct SkirtDraft {
  Point2 cbWaist, cfWaist, sideWaistBack, sideWaistFront, hipBack, hipFront, hemSideBack,
      hemSideFront, cbHem, cfHem;
};

SkirtDraft draftSkirt(DraftBuilder& b, const SkirtOptions& o, bool addSideSeam = true);

/// A skirt that takes the darts of the piece above (SkirtOptions::backDartsAbove and
/// frontDartsAbove): its side intake per side seam edge (negative: the side runs out above the
/// hip) and the side line's shift toward the front at the hip. nullopt when no such skirt
/// exists or the options give no darts above.
struct SkirtSideFit {
  double sideIntake = 0, shift = 0;
};
std::optional<SkirtSideFit> fitSkirtSide(const SkirtOptions& o);

// ---- sleeve ---------------------------------------------------------------------------------
struct SleeveOptions {
  Point2 origin;            // cap top in the draft
  double fah = 0, bah = 0;  // bodice armholes (dart closed)
  double capHeight = 0;
  double capEase = 3;       // total cap ease, shared front/back in proportion to FAH/BAH
  double armLength = 0;     // shoulder tip -> wrist (full sleeve length)
  double lengthFactor = 1;  // sleeve_length
  double wristOpening = 0;  // hem width of a full-length sleeve
  double outFront = 1.8, outBack = 1.9, inFront = 1.3, inBack = 0.6;  // cap guide offsets
};

struct SleeveDraft {
  Point2 top, underFront, underBack, hemFront, hemBack;
  Polyline capFront;  // underFront -> top (cap sleeve: hemFront -> top, the part that is cut)
  Polyline capBack;   // top -> underBack (cap sleeve: top -> hemBack)
  double easeFront = 0, easeBack = 0;        // cap ease of the whole cap, front and back halves
  double capFrontFull = 0, capBackFull = 0;  // lengths of the whole drafted cap halves
  // Cap sleeve: the sleeve ends at or above the underarm (no underarm seam); the hem is the
  // straight line hemBack -> hemFront across the cap, drawn through two inner points so the
  // outline has the same vertex count as a sleeve with an underarm seam (DSW regions).
  bool capOnly = false;
  Polyline hemLine;  // hemBack -> hemFront (2 points, 4 for a cap sleeve)
};

SleeveDraft draftSleeve(DraftBuilder& b, const SleeveOptions& o);

/// Adds the sleeve panel and its seams; when the bodice panels are given, the armhole seams too.
void addSleevePanel(DraftBuilder& b, const SleeveDraft& s, const std::string& bodiceBack,
                    const Point2& backArmholeFrom, const Point2& backArmholeTo,
                    const std::string& bodiceFront, const Point2& frontArmholeFrom,
                    const Point2& frontArmholeTo);

/// Cap height from the bodice (Bunka: 5/6 of the mean armhole depth, dart closed) times `factor`.
double bunkaCapHeight(const BodiceDraft& d, double factor = 1.0);

}  // namespace garmcap::drafts::detail
