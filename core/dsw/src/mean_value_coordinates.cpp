#include "garmcap/dsw/mean_value_coordinates.h"

#include <cmath>
#include <limits>
#include <vector>

#include "boundary_coordinates.h"

namespace garmcap::dsw {
namespace {

// tan(α/2) of the signed angle at the query between s_i and s_{i+1}, by the form that does
// not cancel: for D ≥ 0 (α near 0, exterior points near an edge's extension line) the
// denominator r r' + D has no cancellation; for D < 0 (α near ±π, points near an edge) the
// numerator r r' − D has none.
inline double halfAngleTan(double det, double dot, double rr) {
  return dot >= 0 ? det / (rr + dot) : (rr - dot) / det;
}

// One row the slow, careful way, for the few points the batched kernel flags: exactly on a
// vertex or an edge, or with weights that overflow or underflow.
std::optional<std::string> exactRow(const Points& polygon, double x, double y, Eigen::Index row,
                                    Eigen::MatrixXd& weights) {
  const Eigen::Index n = polygon.rows();
  auto out = weights.row(row);
  if (boundaryCoordinates(polygon, x, y, 0.0, out))
    return std::nullopt;
  std::vector<double> sx(static_cast<std::size_t>(n)), sy(sx.size()), r(sx.size());
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    sx[k] = polygon(i, 0) - x;
    sy[k] = polygon(i, 1) - y;
    r[k] = std::hypot(sx[k], sy[k]);  // hypot: no overflow or underflow of the squares
  }
  std::vector<double> t(sx.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    const std::size_t j = (i + 1) % t.size();
    const double det = sx[i] * sy[j] - sy[i] * sx[j];
    const double dot = sx[i] * sx[j] + sy[i] * sy[j];
    t[i] = (det == 0 && dot >= 0) ? 0.0 : halfAngleTan(det, dot, r[i] * r[j]);
  }
  double sum = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double w = (t[(i + t.size() - 1) % t.size()] + t[i]) / r[i];
    out(static_cast<Eigen::Index>(i)) = w;
    sum += w;
  }
  if (std::isfinite(sum) && sum != 0 && out.allFinite()) {
    out /= sum;
    if (out.allFinite())
      return std::nullopt;
  }
  // Within rounding of the boundary (weights overflowed): the boundary limit is the answer.
  const double tol = 1e-13 * boundingDiagonal(polygon);
  if (boundaryCoordinates(polygon, x, y, tol, out))
    return std::nullopt;
  out.setZero();
  return "point " + std::to_string(row) + " (" + std::to_string(x) + ", " + std::to_string(y) +
         "): mean value weights cannot be normalised (point too far from the polygon)";
}

}  // namespace

std::optional<std::string> meanValueCoordinatesUnchecked(const Points& polygon,
                                                         const Points& points,
                                                         Eigen::MatrixXd& weights) {
  const Eigen::Index n = polygon.rows();
  const Eigen::Index m = points.rows();
  weights.resize(m, n);
  if (m == 0)
    return std::nullopt;
  const double* px = points.col(0).data();
  const double* py = points.col(1).data();

  // Scratch columns: s and r of vertex i and i+1, tan(α/2) of the previous edge.
  Eigen::ArrayXXd scratch(m, 9);
  double* sx0 = &scratch(0, 0);
  double* sy0 = &scratch(0, 1);
  double* r0 = &scratch(0, 2);
  double* sxa = &scratch(0, 3);
  double* sya = &scratch(0, 4);
  double* ra = &scratch(0, 5);
  double* tFirst = &scratch(0, 6);
  double* tPrev = &scratch(0, 7);
  double* sum = &scratch(0, 8);
  Eigen::ArrayXXd scratchB(m, 3);
  double* sxb = &scratchB(0, 0);
  double* syb = &scratchB(0, 1);
  double* rb = &scratchB(0, 2);

  const double vx0 = polygon(0, 0);
  const double vy0 = polygon(0, 1);
  for (Eigen::Index k = 0; k < m; ++k) {
    sx0[k] = vx0 - px[k];
    sy0[k] = vy0 - py[k];
    r0[k] = std::sqrt(sx0[k] * sx0[k] + sy0[k] * sy0[k]);
    sxa[k] = sx0[k];
    sya[k] = sy0[k];
    ra[k] = r0[k];
    sum[k] = 0;
  }
  // Walk the edges i -> i+1; column i gets (t_{i-1} + t_i) / r_i once t_i is known. Column 0
  // is finished last, when t_{n-1} is known.
  for (Eigen::Index i = 0; i < n; ++i) {
    const bool last = i + 1 == n;
    const double* sxn = last ? sx0 : sxb;
    const double* syn = last ? sy0 : syb;
    const double* rn = last ? r0 : rb;
    if (!last) {
      const double vx = polygon(i + 1, 0);
      const double vy = polygon(i + 1, 1);
      for (Eigen::Index k = 0; k < m; ++k) {
        sxb[k] = vx - px[k];
        syb[k] = vy - py[k];
        rb[k] = std::sqrt(sxb[k] * sxb[k] + syb[k] * syb[k]);
      }
    }
    double* col = weights.col(i).data();
    double* tOut = i == 0 ? tFirst : tPrev;
    for (Eigen::Index k = 0; k < m; ++k) {
      const double det = sxa[k] * syn[k] - sya[k] * sxn[k];
      const double dot = sxa[k] * sxn[k] + sya[k] * syn[k];
      const double rr = ra[k] * rn[k];
      const bool pos = dot >= 0;
      const double num = pos ? det : rr - dot;
      const double den = pos ? rr + dot : det;
      const double t = num / den;
      if (i > 0) {
        const double w = (tPrev[k] + t) / ra[k];
        col[k] = w;
        sum[k] += w;
      }
      tOut[k] = t;
    }
    if (i == 0) {
      // t_0 is in tFirst; tPrev must hold t_0 for column 1.
      for (Eigen::Index k = 0; k < m; ++k)
        tPrev[k] = tFirst[k];
    }
    if (last) {
      double* col0 = weights.col(0).data();
      for (Eigen::Index k = 0; k < m; ++k) {
        const double w = (tPrev[k] + tFirst[k]) / r0[k];
        col0[k] = w;
        sum[k] += w;
      }
    } else {
      std::swap(sxa, sxb);
      std::swap(sya, syb);
      std::swap(ra, rb);
    }
  }
  // Normalise; rows whose sum is not a finite non-zero number are the special points.
  std::vector<Eigen::Index> special;
  for (Eigen::Index k = 0; k < m; ++k) {
    if (!std::isfinite(sum[k]) || sum[k] == 0)
      special.push_back(k);
    sum[k] = 1.0 / sum[k];
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    double* col = weights.col(i).data();
    for (Eigen::Index k = 0; k < m; ++k)
      col[k] *= sum[k];
  }
  for (const Eigen::Index k : special) {
    if (auto problem = exactRow(polygon, px[k], py[k], k, weights))
      return problem;
  }
  return std::nullopt;
}

Expected<Eigen::MatrixXd> meanValueCoordinates(const Points& polygon, const Points& points) {
  if (auto problem = cageProblem(polygon))
    return Error{"mean value coordinates: " + *problem};
  if (auto problem = pointsProblem(points))
    return Error{"mean value coordinates: " + *problem};
  Eigen::MatrixXd weights;
  if (auto problem = meanValueCoordinatesUnchecked(polygon, points, weights))
    return Error{"mean value coordinates: " + *problem};
  return weights;
}

}  // namespace garmcap::dsw
