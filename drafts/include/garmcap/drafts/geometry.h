#pragma once
// Geometry construction kernel for drafts: the drafting operations of seed §3.1 on Eigen 2-D
// points. Include this umbrella header; the declarations live in one header per unit:
//
//   geometry_lines.h     angles, points along directions, parallel/perpendicular lines,
//                        line-line / line-circle / circle-circle intersections, mirror, rotate
//   geometry_curves.h    cubic Bézier, smooth curves through guide points (centripetal
//                        Catmull-Rom tangents, optional fixed tangents), flattening at a chord
//                        tolerance and sampling at a fixed vertex count
//   geometry_polyline.h  arc length, point at arc length, division into equal parts, sub-curves,
//                        trimming and extending, polyline-line and polyline-polyline
//                        intersections, closest point
//   geometry_polygon.h   signed area and orientation, simplicity (self-intersection), point in
//                        polygon
//
// Conventions (everywhere in drafts):
// * Units are cm. x to the right, y DOWN (paper/SVG): the neck has a smaller y than the hem.
// * Angles are in DEGREES, measured in the raw coordinates: angle 0 points along +x, angle 90
//   along +y, i.e. DOWN the page. A positive angle therefore turns clockwise as seen on paper.
//   "15° below horizontal, toward +x" is angle +15; "up the page" is -90 (or 270).
// * Lines are infinite unless a function says "segment". Polylines are open point sequences;
//   polygons are closed point sequences whose first point is NOT repeated at the end.
// * Degenerate input that a recipe can produce from absurd measurements (parallel lines,
//   circles that do not meet, a polyline of zero length) is reported as std::nullopt or an
//   empty vector, never as NaN; programming errors (a count < 2, an empty polyline where one
//   point is required) throw std::invalid_argument with the function name.

#include "garmcap/drafts/geometry_curves.h"
#include "garmcap/drafts/geometry_lines.h"
#include "garmcap/drafts/geometry_polygon.h"
#include "garmcap/drafts/geometry_polyline.h"
