#include "garmcap/dsw/coordinates.h"

#include "garmcap/dsw/green_coordinates.h"
#include "garmcap/dsw/mean_value_coordinates.h"
#include "garmcap/dsw/triangle_coordinates.h"
#include "garmcap/dsw/wachspress_coordinates.h"

namespace garmcap::dsw {

std::optional<CoordMethod> parseCoordMethod(std::string_view name) {
  if (name == "mvc")
    return CoordMethod::kMeanValue;
  if (name == "wachspress")
    return CoordMethod::kWachspress;
  if (name == "green")
    return CoordMethod::kGreen;
  if (name == "tbc")
    return CoordMethod::kTriangle;
  return std::nullopt;
}

std::string_view coordMethodName(CoordMethod method) {
  switch (method) {
    case CoordMethod::kMeanValue:
      return "mvc";
    case CoordMethod::kWachspress:
      return "wachspress";
    case CoordMethod::kGreen:
      return "green";
    case CoordMethod::kTriangle:
      return "tbc";
  }
  return "mvc";
}

namespace {

Expected<Encoding> encode(CoordMethod method, const Points& polygon, const Points& points,
                          bool cageChecked) {
  Encoding enc;
  enc.method = method;
  switch (method) {
    case CoordMethod::kMeanValue: {
      if (!cageChecked) {
        auto w = meanValueCoordinates(polygon, points);
        if (!w)
          return w.error();
        enc.weights = std::move(w).value();
        break;
      }
      if (auto problem = pointsProblem(points))
        return Error{"mean value coordinates: " + *problem};
      if (auto problem = meanValueCoordinatesUnchecked(polygon, points, enc.weights))
        return Error{"mean value coordinates: " + *problem};
      break;
    }
    case CoordMethod::kWachspress: {
      auto w = wachspressCoordinates(polygon, points);
      if (!w)
        return w.error();
      enc.weights = std::move(w).value();
      break;
    }
    case CoordMethod::kTriangle: {
      auto w = triangleCoordinates(polygon, points);
      if (!w)
        return w.error();
      enc.weights = std::move(w).value();
      break;
    }
    case CoordMethod::kGreen: {
      auto gc = greenCoordinates(polygon, points);
      if (!gc)
        return gc.error();
      GreenCoordinates g = std::move(gc).value();
      enc.weights = std::move(g.vertexWeights);
      enc.edgeWeights = std::move(g.edgeWeights);
      enc.edgeLengthsCm = std::move(g.edgeLengthsCm);
      enc.orientation = g.orientation;
      break;
    }
  }
  return enc;
}

}  // namespace

Expected<Encoding> encodePoints(CoordMethod method, const Points& polygon, const Points& points) {
  return encode(method, polygon, points, false);
}

Expected<Encoding> encodePointsInCheckedCage(CoordMethod method, const Points& polygon,
                                             const Points& points) {
  return encode(method, polygon, points, true);
}

Expected<Points> decodePoints(const Encoding& encoding, const Points& target) {
  if (target.rows() != encoding.weights.cols())
    return Error{"decode: target polygon has " + std::to_string(target.rows()) +
                 " vertices, the encoding " + std::to_string(encoding.weights.cols())};
  if (auto problem = pointsProblem(target))
    return Error{"decode: target polygon " + *problem};
  if (encoding.method == CoordMethod::kGreen) {
    GreenCoordinates g{encoding.weights, encoding.edgeWeights, encoding.edgeLengthsCm,
                       encoding.orientation};
    return greenDecode(g, target);
  }
  // Two matrix-vector products: for an N×2 right-hand side Eigen's blocked matrix product
  // spends more time packing its operands than multiplying.
  Points out(encoding.weights.rows(), 2);
  out.col(0).noalias() = encoding.weights * target.col(0);
  out.col(1).noalias() = encoding.weights * target.col(1);
  return out;
}

}  // namespace garmcap::dsw
