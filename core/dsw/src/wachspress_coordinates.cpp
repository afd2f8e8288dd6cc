#include "garmcap/dsw/wachspress_coordinates.h"

#include <cmath>
#include <vector>

#include "boundary_coordinates.h"

namespace garmcap::dsw {
namespace {

// Product form w_i = C_i · Π_{j ≠ i-1, i} A_j, free of divisions, for points where some
// A_j vanishes (on an edge's supporting line outside the polygon). Areas are scaled by the
// squared cage size so that the products of N-2 factors stay in range for drafts.
bool productRow(const Points& polygon, const std::vector<double>& c, double x, double y,
                double scale2, Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>> out) {
  const std::size_t n = c.size();
  std::vector<double> a(n);
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t k = (j + 1) % n;
    const auto ej = static_cast<Eigen::Index>(j), ek = static_cast<Eigen::Index>(k);
    a[j] = ((polygon(ej, 0) - x) * (polygon(ek, 1) - y) -
            (polygon(ej, 1) - y) * (polygon(ek, 0) - x)) /
           scale2;
  }
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    double w = c[i];
    const std::size_t prev = (i + n - 1) % n;
    for (std::size_t j = 0; j < n; ++j) {
      if (j != prev && j != i)
        w *= a[j];
    }
    out(static_cast<Eigen::Index>(i)) = w;
    sum += w;
  }
  if (!std::isfinite(sum) || sum == 0)
    return false;
  out /= sum;
  return out.allFinite();
}

}  // namespace

Expected<Eigen::MatrixXd> wachspressCoordinates(const Points& polygon, const Points& points) {
  if (auto problem = cageProblem(polygon))
    return Error{"wachspress coordinates: " + *problem};
  if (!isConvex(polygon))
    return Error{"wachspress coordinates: polygon is not convex (use mvc)"};
  if (auto problem = pointsProblem(points))
    return Error{"wachspress coordinates: " + *problem};
  const Eigen::Index n = polygon.rows();
  const Eigen::Index m = points.rows();
  const double diag = boundingDiagonal(polygon);
  const double scale2 = diag * diag;
  // C_i = det(v_i - v_{i-1}, v_{i+1} - v_i): twice the area of the corner triangle at v_i,
  // scaled like the point areas so that weights stay O(1).
  std::vector<double> c(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index p = (i + n - 1) % n, q = (i + 1) % n;
    c[static_cast<std::size_t>(i)] =
        ((polygon(i, 0) - polygon(p, 0)) * (polygon(q, 1) - polygon(i, 1)) -
         (polygon(i, 1) - polygon(p, 1)) * (polygon(q, 0) - polygon(i, 0))) /
        scale2;
  }
  Eigen::MatrixXd weights(m, n);
  Eigen::ArrayXd area(n);
  for (Eigen::Index k = 0; k < m; ++k) {
    const double x = points(k, 0), y = points(k, 1);
    for (Eigen::Index j = 0; j < n; ++j) {
      const Eigen::Index q = (j + 1) % n;
      area(j) =
          ((polygon(j, 0) - x) * (polygon(q, 1) - y) - (polygon(j, 1) - y) * (polygon(q, 0) - x)) /
          scale2;
    }
    double sum = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double w = c[static_cast<std::size_t>(i)] / (area((i + n - 1) % n) * area(i));
      weights(k, i) = w;
      sum += w;
    }
    if (std::isfinite(sum) && sum != 0) {
      weights.row(k) /= sum;
      if (weights.row(k).allFinite())
        continue;
    }
    if (boundaryCoordinates(polygon, x, y, 0.0, weights.row(k)))
      continue;
    if (productRow(polygon, c, x, y, scale2, weights.row(k)))
      continue;
    if (boundaryCoordinates(polygon, x, y, 1e-13 * diag, weights.row(k)))
      continue;
    return Error{"wachspress coordinates: point " + std::to_string(k) +
                 " lies on a pole of the exterior extension (outside the polygon)"};
  }
  return weights;
}

}  // namespace garmcap::dsw
