#pragma once
// Closed polygons (panel outlines, draft regions): first point NOT repeated at the end.

#include <optional>
#include <utility>

#include "garmcap/drafts/geometry_lines.h"

namespace garmcap::drafts {

/// Shoelace area in the raw coordinates: sum (x_i y_{i+1} - x_{i+1} y_i) / 2. Positive when
/// the vertices turn from +x toward +y, i.e. CLOCKWISE AS SEEN ON PAPER/SVG (y down), and
/// counter-clockwise in the usual mathematical (y-up) reading of the same numbers.
double signedArea(const Polyline& polygon);
double polygonArea(const Polyline& polygon);  // |signedArea|
/// Perimeter including the closing edge.
double polygonPerimeter(const Polyline& polygon);
/// true when signedArea > 0 (see signedArea for what that means on paper).
bool hasPositiveOrientation(const Polyline& polygon);
/// The polygon with vertex order reversed if needed so that signedArea > 0 (keeps vertex 0).
Polyline withPositiveOrientation(const Polyline& polygon);

/// First pair of non-adjacent edges (i, j), i < j, edge i = [P_i, P_{i+1 mod n}], that touch
/// or cross; also reports repeated vertices and an edge folding back on its neighbour.
/// std::nullopt when the polygon is simple. O(n²), fine for a few thousand vertices.
std::optional<std::pair<int, int>> findSelfIntersection(const Polyline& polygon);
/// At least 3 vertices, non-zero area and no self-intersection.
bool isSimplePolygon(const Polyline& polygon);

/// Even-odd point-in-polygon test (points on the boundary may go either way).
bool pointInPolygon(const Point2& p, const Polyline& polygon);

/// The polygon offset by `distanceCm`: outward when positive (a seam allowance / cutting line
/// around a panel outline), inward when negative, whatever the orientation; the result keeps
/// the input's orientation. Each vertex moves to the intersection of its two offset edges
/// (miter); where that point would be farther than `miterLimit` * |distanceCm| from the
/// vertex (a sharp convex corner) the corner is bevelled with two points. Repeated vertices
/// are dropped first. std::nullopt when the input is not a simple polygon or the offset is not
/// simple (e.g. an inward offset wider than the polygon, or a notch narrower than the offset).
std::optional<Polyline> offsetPolygon(const Polyline& polygon, double distanceCm,
                                      double miterLimit = 4.0);

}  // namespace garmcap::drafts
