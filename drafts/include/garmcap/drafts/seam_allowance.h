#pragma once
// Seam allowance: the cut line of a panel, its net outline (the sew line) offset outward by
// each edge's allowance. Defaults (docs/exports.md, "Seam allowance"): seams and free edges
// (neckline, armhole without sleeve, waist without waistband) take the panel's
// seamAllowanceCm (design parameter `seam_allowance`, 1 cm), the hem 3 cm, a fold edge none.
// Corners are mitred (the two offset edges intersected) and bevelled only where a convex
// corner is so sharp that the mitre would reach beyond 4 x the allowance; hem corners are
// trued (the side's cut line mirrored about the hem line, as the turned-up hem needs it). A dart
// opening in the outline is crossed by the dart cap a pattern maker draws: the cut line of the
// closed dart, its intake pressed toward the centre line (vertical darts) or down (horizontal
// ones).

#include <stdexcept>
#include <vector>

#include "garmcap/drafts/pattern.h"

namespace garmcap::drafts {

inline constexpr double kHemAllowanceCm = 3.0;

/// What an outline edge is when the piece is cut and sewn.
enum class EdgeRole {
  Seam,  // sewn to another edge (a SeamPair of the pattern)
  Free,  // finished alone (neckline, armhole of a sleeveless piece, waist without band)
  Hem,   // the free edge at the bottom of the piece: the free run holding its lowest vertex
  Fold,  // the fold of a cut-on-fold piece (foldEdge): nothing added
  Dart,  // a leg of a dart opened in the outline: crossed by the dart cap
};

const char* edgeRoleName(EdgeRole role);

/// A panel whose cut line cannot be built (a dart whose legs are not outline vertices, an
/// offset that crosses itself); the message names the panel.
class SeamAllowanceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The dart's sewn legs: the outline from one leg to the other through the apex when the dart
/// is opened in the outline (a dart whose legs follow a bodice dart first, as the high-waist
/// skirt's, bends there), else leg1, apex, leg2.
Polyline dartPath(const Panel& panel, const Dart& dart);

/// One role per outline edge i -> i+1 (wrapping), decided from the pattern's seams, the fold
/// edge and the darts whose legs are outline vertices.
std::vector<EdgeRole> edgeRoles(const Panel& panel, const Pattern& pattern);

/// The allowance in cm of each outline edge (0 on the fold and on dart legs).
std::vector<double> edgeAllowances(const Panel& panel, const Pattern& pattern);

/// The cut line: a closed simple polygon (first point not repeated) enclosing the outline, in
/// the outline's orientation, each edge at its allowance from the net edge. Throws
/// SeamAllowanceError when it cannot be built.
Polyline cutOutline(const Panel& panel, const Pattern& pattern);

}  // namespace garmcap::drafts
