#pragma once
// Measuring finished panels the way the seed's table 4.3 measures graded panels: garment
// circumferences are sums of panel widths at a level times the number of pieces (darts closed),
// lengths are taken between draft landmarks on the panels. Every value is a GARMENT value in cm
// (body measurement + ease), reported under the body measurement's Valentina name where one
// exists (`bust_circ` = garment bust circumference) and under documented names otherwise
// (`skirt_length`, `sleeve_cap_length`, ...). See docs/drafts.md for the list per type.

#include <map>
#include <optional>
#include <string>

#include "garmcap/drafts/pattern.h"

namespace garmcap::drafts {

/// Sewn length of an edge: the outline length from `edge.from` forward to `edge.to`, with
/// every dart of the panel whose legs and apex lie inside the edge left out (the dart is
/// closed when the seam is sewn). Throws std::out_of_range naming the panel on bad indices.
double sewnEdgeLength(const Panel& panel, const EdgeRef& edge);

/// Total width of the panel on the horizontal line y = levelCm: sum of the lengths of the
/// intervals of the line inside the outline (dart openings fall outside and so are excluded).
double panelWidthAtLevel(const Panel& panel, double levelCm);

/// Length of the panel's hem: the outline edges seam_allowance.h's edgeRoles calls Hem (the run
/// of free edges holding the lowest vertex), whatever the draft points say. 0 without a hem.
double hemEdgeLength(const Panel& panel, const Pattern& pattern);

/// Index of the outline vertex nearest to `p`; std::nullopt when none is within `toleranceCm`.
std::optional<int> nearestOutlineVertex(const Panel& panel, const Point2& p,
                                        double toleranceCm = 0.5);

/// Garment measurements of the pattern (keys documented in docs/drafts.md). Uses the pattern's
/// type, its named draft points (levels and landmarks) and its panels. Measurements that the
/// pattern cannot show (no sleeve, no skirt, ...) are absent. Throws DraftError naming the
/// pattern type and the missing point or panel when the pattern lacks what its type needs.
std::map<std::string, double> measurePattern(const Pattern& pattern);

}  // namespace garmcap::drafts
