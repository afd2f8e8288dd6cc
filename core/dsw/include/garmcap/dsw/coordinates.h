#pragma once
// One entry point for every coordinate method: encode points against a source cage, decode
// them against a target cage with the same vertex order. Decoding is one matrix product
// (plus the edge term for Green coordinates).

#include <Eigen/Core>
#include <optional>
#include <string>
#include <string_view>

#include "garmcap/dsw/expected.h"
#include "garmcap/dsw/polygon.h"

namespace garmcap::dsw {

enum class CoordMethod {
  kMeanValue,   // "mvc": any simple polygon, whole plane (the default for grading)
  kWachspress,  // "wachspress": convex polygons only
  kGreen,       // "green": inside only; conformal (comparison)
  kTriangle,    // "tbc": barycentric in a triangle of an ear-clipping triangulation
};

/// "mvc", "wachspress", "green", "tbc" <-> CoordMethod. parse returns nullopt for others.
std::optional<CoordMethod> parseCoordMethod(std::string_view name);
std::string_view coordMethodName(CoordMethod method);

/// Points encoded against one cage.
struct Encoding {
  CoordMethod method = CoordMethod::kMeanValue;
  Eigen::MatrixXd weights;        // M×N vertex weights (φ for Green)
  Eigen::MatrixXd edgeWeights;    // M×N Green edge weights ψ; empty for the other methods
  Eigen::VectorXd edgeLengthsCm;  // Green only: source edge lengths (stretch factors)
  double orientation = 1;         // Green only: sign of the source cage's area
};

/// Encodes `points` (M×2) against `polygon` (N×2). Errors as the method's function.
Expected<Encoding> encodePoints(CoordMethod method, const Points& polygon, const Points& points);

/// As encodePoints, for a cage the caller has already checked with cageProblem() (grading
/// checks each draft region once and encodes several point sets against it): mean value
/// coordinates then skip that O(N²) check; the other methods run their own checks as usual.
Expected<Encoding> encodePointsInCheckedCage(CoordMethod method, const Points& polygon,
                                             const Points& points);

/// Decodes against `target` (N×2, same vertex order as the source cage). M×2. Errors: vertex
/// count differs, non-finite target, or (Green) a zero-length target edge.
Expected<Points> decodePoints(const Encoding& encoding, const Points& target);

}  // namespace garmcap::dsw
