#pragma once
// Mean value coordinates (Floater 2003; Hormann & Floater 2006, "Mean value coordinates for
// arbitrary planar polygons") for any simple polygon and any point of the plane: inside,
// outside, on an edge or on a vertex. Not the seed's eq. 4.13 (which divides by the squared
// distance) nor its appendix A algorithm 4 (NaN on a vertex); see docs/dsw.md.

#include <Eigen/Core>

#include "garmcap/dsw/expected.h"
#include "garmcap/dsw/polygon.h"

namespace garmcap::dsw {

/// Weights of `points` (M×2) with respect to the cage `polygon` (N×2, any orientation).
/// Returns M×N, row k the coordinates of point k: rows sum to 1 and reproduce the point
/// (linear precision); a point on vertex i gets the unit row e_i, a point on an edge the two
/// segment coordinates. tan(α/2) is taken as det/(r·r'+D) where the dot product D ≥ 0 and as
/// (r·r'−D)/det where D < 0, so neither form cancels (research/anchors_algorithms.md §2).
/// Errors: the cage fails cageProblem(), a point is not finite, or a point's weights have no
/// finite normalisation (only for points so far away that the weights underflow).
Expected<Eigen::MatrixXd> meanValueCoordinates(const Points& polygon, const Points& points);

/// The same kernel without the O(N²) cage check, for callers that checked the cage once and
/// encode many point sets against it (grading, benchmarks). `weights` is resized to M×N.
/// Returns an error message naming the point when a row cannot be normalised, else nullopt.
std::optional<std::string> meanValueCoordinatesUnchecked(const Points& polygon,
                                                         const Points& points,
                                                         Eigen::MatrixXd& weights);

}  // namespace garmcap::dsw
