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

// One edge (i -> i+1) for all points: reads s_i, r_i (a*) and t_{i-1} (tPrev), computes s_{i+1},
// r_{i+1} into b* (unless `next` is given: the wrap-around to vertex 0), t_i, and column i =
// (t_{i-1} + t_i) / r_i. Plain loops over restrict pointers so that GCC vectorises them; built
// for AVX2 as well where the CPU has it (ifunc dispatch), SSE2 otherwise.
__attribute__((target_clones("avx2", "default"))) void edgeColumns(
    Eigen::Index m, const double* __restrict px, const double* __restrict py, double vx, double vy,
    const double* __restrict sxa, const double* __restrict sya, const double* __restrict ra,
    double* __restrict sxb, double* __restrict syb, double* __restrict rb, double* __restrict tPrev,
    double* __restrict col, double* __restrict sum) {
  for (Eigen::Index k = 0; k < m; ++k) {
    const double bx = vx - px[k];
    const double by = vy - py[k];
    const double rn = std::sqrt(bx * bx + by * by);
    sxb[k] = bx;
    syb[k] = by;
    rb[k] = rn;
    const double det = sxa[k] * by - sya[k] * bx;
    const double dot = sxa[k] * bx + sya[k] * by;
    const double rr = ra[k] * rn;
    // Both candidate forms are computed, then selected: branch-free, so it vectorises.
    const double plus = rr + dot;
    const double minus = rr - dot;
    const bool pos = dot >= 0;
    const double num = pos ? det : minus;
    const double den = pos ? plus : det;
    const double t = num / den;
    const double w = (tPrev[k] + t) / ra[k];
    col[k] = w;
    sum[k] += w;
    tPrev[k] = t;
  }
}

// First edge (0 -> 1) and the starting arrays: s_0, r_0 into a*, s_1, r_1 into b*, t_0 into
// tPrev and tFirst.
__attribute__((target_clones("avx2", "default"))) void firstEdge(
    Eigen::Index m, const double* __restrict px, const double* __restrict py, double v0x,
    double v0y, double v1x, double v1y, double* __restrict sxa, double* __restrict sya,
    double* __restrict ra, double* __restrict sxb, double* __restrict syb, double* __restrict rb,
    double* __restrict tPrev, double* __restrict tFirst, double* __restrict sum) {
  for (Eigen::Index k = 0; k < m; ++k) {
    const double ax = v0x - px[k];
    const double ay = v0y - py[k];
    const double r0 = std::sqrt(ax * ax + ay * ay);
    const double bx = v1x - px[k];
    const double by = v1y - py[k];
    const double r1 = std::sqrt(bx * bx + by * by);
    sxa[k] = ax;
    sya[k] = ay;
    ra[k] = r0;
    sxb[k] = bx;
    syb[k] = by;
    rb[k] = r1;
    const double det = ax * by - ay * bx;
    const double dot = ax * bx + ay * by;
    const double rr = r0 * r1;
    // Both candidate forms are computed, then selected: branch-free, so it vectorises.
    const double plus = rr + dot;
    const double minus = rr - dot;
    const bool pos = dot >= 0;
    const double num = pos ? det : minus;
    const double den = pos ? plus : det;
    const double t = num / den;
    tPrev[k] = t;
    tFirst[k] = t;
    sum[k] = 0;
  }
}

// Closes the ring: column 0 = (t_{n-1} + t_0) / r_0, then normalises every column.
__attribute__((target_clones("avx2", "default"))) void closeAndNormalise(
    Eigen::Index m, Eigen::Index n, const double* __restrict r0, const double* __restrict tPrev,
    const double* __restrict tFirst, double* __restrict weights, double* __restrict sum) {
  for (Eigen::Index k = 0; k < m; ++k) {
    const double w = (tPrev[k] + tFirst[k]) / r0[k];
    weights[k] = w;
    sum[k] = 1.0 / (sum[k] + w);
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    double* __restrict col = weights + i * m;
    for (Eigen::Index k = 0; k < m; ++k)
      col[k] *= sum[k];
  }
}

}  // namespace

std::optional<std::string> meanValueCoordinatesUnchecked(const Points& polygon,
                                                         const Points& points,
                                                         Eigen::MatrixXd& weights) {
  const Eigen::Index n = polygon.rows();
  const Eigen::Index m = points.rows();
  weights.resize(m, n);
  if (m == 0 || n < 2)
    return n < 2 ? std::optional<std::string>("polygon has fewer than 2 vertices") : std::nullopt;
  const double* px = points.col(0).data();
  const double* py = points.col(1).data();
  // Scratch: s and r of vertex 0, of the current vertex i and of i+1 (ping-pong), t_{i-1},
  // t_0 and the row sums.
  Eigen::ArrayXXd scratch(m, 12);
  auto colPtr = [&](int c) { return &scratch(0, c); };
  double* sxa = colPtr(0);
  double* sya = colPtr(1);
  double* ra = colPtr(2);
  double* sxb = colPtr(3);
  double* syb = colPtr(4);
  double* rb = colPtr(5);
  double* sx0 = colPtr(6);
  double* sy0 = colPtr(7);
  double* r0 = colPtr(8);
  double* tPrev = colPtr(9);
  double* tFirst = colPtr(10);
  double* sum = colPtr(11);
  firstEdge(m, px, py, polygon(0, 0), polygon(0, 1), polygon(1, 0), polygon(1, 1), sx0, sy0, r0,
            sxa, sya, ra, tPrev, tFirst, sum);
  // Edges 1 .. n-1; edge n-1 wraps to vertex 0, whose s and r are recomputed into b (cheaper
  // than a special loop, and bit-identical).
  for (Eigen::Index i = 1; i < n; ++i) {
    const Eigen::Index j = (i + 1) % n;
    edgeColumns(m, px, py, polygon(j, 0), polygon(j, 1), sxa, sya, ra, sxb, syb, rb, tPrev,
                weights.col(i).data(), sum);
    std::swap(sxa, sxb);
    std::swap(sya, syb);
    std::swap(ra, rb);
  }
  closeAndNormalise(m, n, r0, tPrev, tFirst, weights.data(), sum);
  // Rows whose sum was not a finite non-zero number are the special points: on a vertex or an
  // edge, or with overflowing weights. sum now holds 1/Σw.
  for (Eigen::Index k = 0; k < m; ++k) {
    if (!std::isfinite(sum[k]) || sum[k] == 0) {
      if (auto problem = exactRow(polygon, px[k], py[k], k, weights))
        return problem;
    }
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
