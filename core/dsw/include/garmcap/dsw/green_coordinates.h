#pragma once
// 2D Green coordinates (Lipman, Levin & Cohen-Or 2008), with the corrections of
// research/anchors_algorithms.md §3 (the seed's appendix A algorithm 3 reverses the edge
// vector, assigns instead of accumulating, drops ψ's sign and normalises ψ). For comparison
// only: they are conformal, not affine, and send exterior points to the origin, so they are
// not used for grading by default.

#include <Eigen/Core>

#include "garmcap/dsw/expected.h"
#include "garmcap/dsw/polygon.h"

namespace garmcap::dsw {

struct GreenCoordinates {
  Eigen::MatrixXd vertexWeights;  // M×N: φ_i(η); rows sum to 1 inside, 0 outside
  Eigen::MatrixXd edgeWeights;  // M×N: ψ_j(η) for edge j = (v_j -> v_{j+1}); multiplies s_j n_j
  Eigen::VectorXd edgeLengthsCm;  // N: source edge lengths, for the stretch factors s_j
  double orientation = 1;         // +1 when the source cage has positive signed area, else -1
};

/// Green coordinates of `points` (M×2) for the cage `polygon` (N×2, any orientation). Points
/// on the boundary get the limit from the inside (the double-layer jump added back).
/// Errors: the cage fails cageProblem() or has a zero-length edge (no normal), or a point is
/// not finite.
Expected<GreenCoordinates> greenCoordinates(const Points& polygon, const Points& points);

/// Decodes with the deformed cage `target` (N×2, same vertex order): η' = Σ φ_i v'_i +
/// Σ ψ_j s_j n'_j, with n'_j the outward unit normal of target edge j and s_j = |a'_j|/|a_j|
/// the edge-stretch factor. Returns M×2. Errors: target has a zero-length edge or a
/// different vertex count.
Expected<Points> greenDecode(const GreenCoordinates& coordinates, const Points& target);

}  // namespace garmcap::dsw
