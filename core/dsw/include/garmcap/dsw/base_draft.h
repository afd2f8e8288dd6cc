#pragma once
// Base-draft grading (seed §4.4): when no recipe matches the garment, panels are encoded
// against a base block drawn from a few measurements instead of the garment's own draft. The
// result is close to linear grading; parts that depend on other measurements (armhole,
// neckline, darts) are not graded specifically.

#include <vector>

#include "garmcap/drafts/measurements.h"
#include "garmcap/drafts/pattern.h"
#include "garmcap/dsw/coordinates.h"
#include "garmcap/dsw/expected.h"

namespace garmcap::dsw {

/// The base block for `body`: three regions with fixed vertex counts, y down, cm.
///  - "base_top": the Bunka bodice frame, B/2 wide (B = bust_circ), from the back neck (y 0)
///    to the waist (y = neck_back_to_waist_b), with vertices at the bust line
///    (y = B/12 + 13.7, Bunka) and at the half width;
///  - "base_skirt": H/2 wide (H = hip_circ), from the waist down by skirt_length (the body's
///    `skirt_length`, else `fallbackSkirtLengthCm`), with vertices at the hip line
///    (waist_to_hip_b below the waist) and the half width;
///  - "base_sleeve": cap top, biceps corners (width AH = armscye_circ, or bust_circ/2 when the
///    body lacks it; cap height AH/4 + 2.5, Bunka) and wrist corners (arm_wrist_circ wide,
///    arm_shoulder_tip_to_wrist long), placed right of the top.
/// Errors name a missing measurement.
Expected<std::vector<drafts::DraftRegion>> baseBlock(const drafts::Measurements& body,
                                                     double fallbackSkirtLengthCm);

/// Grades `source` to `target` through the base blocks of the two bodies: sleeves (panels whose
/// name contains "sleeve") encode against base_sleeve, panels whose name contains "skirt"
/// against base_skirt, every other panel against base_top and base_skirt (one-piece panels
/// cross the waist). Panels are positioned by bounding-box alignment per group (§4.2). The
/// result carries the target recipe's draft points when the type has a recipe (so it can be
/// measured), else the source's.
Expected<drafts::Pattern> gradeWithBaseDraft(const drafts::Pattern& source,
                                             const drafts::Measurements& target,
                                             CoordMethod method);

}  // namespace garmcap::dsw
