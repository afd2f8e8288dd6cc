#pragma once
// What each stretch of a panel outline is when the piece is cut: a seam (sewn to another edge),
// the fold (the cloth is folded there, nothing to sew or add), or a free edge (hem, neckline,
// waist without a waistband). Used by the pattern file writers for seam allowance, mirror lines
// and unfolding.

#include <optional>
#include <string>
#include <vector>

#include "garmcap/drafts/pattern.h"

namespace garmcap::drafts {

/// Whether the two outlines of a seam pair run the same way along it (a.from meets b.from)
/// rather than opposite ways (a.from meets b.to): set-in sleeve caps against their armholes and
/// trousers' outseam and inseam, as documented in docs/drafts.md (seam pairs).
bool seamRunsSameWay(const SeamPair& seam);

/// Whether the seam joins a piece to its own mirrored twin along the same edge (trousers'
/// centre seams, the centre back of a skirt cut twice).
bool seamJoinsTwins(const SeamPair& seam);

/// The fold of a cut-on-fold panel: the longest run of outline edges lying on one vertical line
/// at the panel's leftmost or rightmost x (within 0.01 mm), outside every seam of `pattern`.
/// std::nullopt when the panel is not cut on the fold or no such straight edge exists (a
/// centre line that leaves the fold cannot be cut on it).
std::optional<EdgeRef> foldEdge(const Panel& panel, const Pattern& pattern);

/// Whether outline edge i -> i+1 lies inside the walk `e` (forward, wrapping).
bool edgeInside(const EdgeRef& e, int i, int vertexCount);

}  // namespace garmcap::drafts
