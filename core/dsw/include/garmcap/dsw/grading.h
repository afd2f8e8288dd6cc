#pragma once
// Draft-space warping (seed chapter 4): grade a pattern's panels to another body through the
// drafts of the two bodies. The five steps of §4.2:
//   1. source draft: the regions in the source pattern (drawn by its recipe for its body);
//   2. panel positioning: panels that overlap their draft regions are kept where they are;
//      others are moved as a group (panels that name the same regions) so that the centre of
//      their bounding box meets that of the regions', and moved back after decoding;
//   3. encoding: every panel point — outline, dart apex and legs, grainline ends, notches,
//      internal-line points — gets generalized barycentric coordinates with respect to one
//      region of the panel's Panel::draftRegions (the region that contains it, else the
//      nearest one), by default mean value coordinates;
//   4. target draft: drafts::draftGarment(type, target body, design);
//   5. decoding: each point = its weights × the same region of the target draft.
// Base-draft grading (§4.4) replaces steps 1 and 4 by a base block drawn from a few
// measurements (base_draft.h), for garments whose type has no recipe. Dart compensation
// (§4.5, eq. 4.14 with its sign corrected) can follow. See docs/dsw.md.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "garmcap/drafts/measurements.h"
#include "garmcap/drafts/pattern.h"
#include "garmcap/dsw/coordinates.h"
#include "garmcap/dsw/expected.h"

namespace garmcap::dsw {

struct GradeOptions {
  CoordMethod method = CoordMethod::kMeanValue;
  bool dartCompensation = false;
  // m of eq. 4.14: garment waist − body waist wanted after grading. Unset (the default): the
  // source pattern's own margin (its measured waist − its body's waist_circ), so compensation
  // keeps the designed waist ease in every size and leaves the base size as it is; set, it
  // overrides that ease (a design change, not a correction).
  std::optional<double> marginCm;
  bool baseDraft = false;  // force base-draft grading even when the type has a recipe
};

/// Every panel point of a pattern encoded against the source draft's regions. Built once,
/// decoded against any number of target drafts (a size run).
class EncodedPattern {
 public:
  struct Group {  // the points of one panel encoded against one region
    std::string region;
    std::size_t panel = 0;
    std::vector<Eigen::Index> slots;  // indices into the panel's flattened point list
    Encoding encoding;
  };
  drafts::Pattern source;                    // the source pattern (panels, seams, design)
  std::vector<Eigen::Vector2d> panelOffset;  // positioning shift per panel (0 when kept)
  std::vector<Group> groups;
  std::vector<std::size_t> pointCount;  // flattened points per panel
};

/// Steps 2 and 3 against `sourceRegions` (normally source.regions). Errors name the panel,
/// the region or the point (a region missing from the draft, a degenerate region polygon, a
/// non-finite panel point).
Expected<EncodedPattern> encodePattern(const drafts::Pattern& source,
                                       const std::vector<drafts::DraftRegion>& sourceRegions,
                                       CoordMethod method);

/// Step 5: the graded panels, placed in a pattern that carries the target draft (its type,
/// measurements, design, points, lines and regions) and the source's seams. Errors name the
/// region whose vertex count differs between the drafts, or a non-finite result.
Expected<drafts::Pattern> decodePattern(const EncodedPattern& encoded,
                                        const drafts::Pattern& targetDraft);

/// The target draft for `target`: the source's recipe with the source's design parameters,
/// except those the body itself carries (skirt_length in the seed's table 4.2 bodies).
Expected<drafts::Pattern> targetDraft(const drafts::Pattern& source,
                                      const drafts::Measurements& target);

/// The source pattern's waist margin: drafts::measurePattern's waist_circ minus its body's
/// waist_circ. Errors when either is missing.
Expected<double> waistMargin(const drafts::Pattern& pattern);

/// All five steps, then dart compensation when asked. Base-draft grading when the pattern's
/// type has no recipe, the pattern has no regions, or options.baseDraft.
Expected<drafts::Pattern> gradePattern(const drafts::Pattern& source,
                                       const drafts::Measurements& target,
                                       const GradeOptions& options = {});

/// Result of dart compensation.
struct DartCompensation {
  double garmentBeforeCm = 0;  // garment waist before
  double garmentAfterCm = 0;   // after
  double bodyCm = 0;           // body waist
  int dartCount = 0;           // N_dart: waist darts over the whole garment (pieces counted)
  double widthChangeCm = 0;    // change of each dart's width (negative: narrower)
};

/// Eq. 4.14 at the waist, with the sign that makes it do what §4.5 says: each waist dart's
/// width changes by −(m + C_body − C_garment)/N_dart, so that the garment waist becomes
/// C_body + m. Both legs of every dart at the waist level move symmetrically along the waist
/// edge; skirt darts under the bodice darts change with them so that the waist seam still
/// matches. C_garment is measured by drafts::measurePattern. Iterates (at most 4 times) until
/// the margin is within 0.01 cm, since legs on a sloped edge change the width slightly
/// differently. Errors: no waist darts, a dart that would close past zero width, or the
/// pattern cannot be measured.
Expected<DartCompensation> compensateDarts(drafts::Pattern& graded, double bodyWaistCm,
                                           double marginCm);

/// Flattened points of a panel in the order the encoder uses (outline, darts apex/leg1/leg2,
/// grainline start/end, notches, internal lines), and the inverse.
std::vector<Eigen::Vector2d> flattenPanel(const drafts::Panel& panel);
void unflattenPanel(const std::vector<Eigen::Vector2d>& points, drafts::Panel& panel);

}  // namespace garmcap::dsw
