#include "garmcap/dsw/mean_value_coordinates.h"

#include <algorithm>
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

// tan(α_i/2) is kept as a fraction num_i/den_i (the form chosen by the sign of D_i, see
// halfAngleTan), so that w_i = (t_{i-1} + t_i)/r_i = (num_{i-1} den_i + num_i den_{i-1}) /
// (den_{i-1} den_i r_i) costs one division instead of two; with the square root for r_{i+1}
// that is what bounds the kernel (the divider does both). den is r r' + D ≥ 0 or det, of the
// order of r², so the product only overflows beyond ~1e60 cm and only vanishes on a vertex or
// an edge: those rows get a non-finite or zero sum and go to exactRow.
struct HalfAngle {
  double num, den;
};
inline HalfAngle halfAngleFraction(double ax, double ay, double ra, double bx, double by,
                                   double rb) {
  const double det = ax * by - ay * bx;
  const double dot = ax * bx + ay * by;
  const double rr = ra * rb;
  // Both candidate forms are computed, then selected: branch-free, so it vectorises.
  const bool pos = dot >= 0;
  return {pos ? det : rr - dot, pos ? rr + dot : det};
}

// Per-block scratch, one array per quantity (structure of arrays): s and r of vertex i (a)
// and i+1 (b), s and r of vertex 0, tan(α/2) of edge i-1 and of edge 0 as fractions, and the
// row sums.
constexpr Eigen::Index kBlock = 256;  // 15 arrays × 2 KiB: the scratch stays in L1
struct Scratch {
  alignas(64) double sxa[kBlock], sya[kBlock], ra[kBlock];
  alignas(64) double sxb[kBlock], syb[kBlock], rb[kBlock];
  alignas(64) double r0[kBlock];
  alignas(64) double numPrev[kBlock], denPrev[kBlock], numFirst[kBlock], denFirst[kBlock];
  alignas(64) double sum[kBlock];
};

// Plain loops over restrict pointers so that GCC vectorises them; built for AVX-512 and AVX2
// as well where the CPU has them (ifunc dispatch), SSE2 otherwise.
#define GARMCAP_MVC_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))

// First edge (0 -> 1): s_0, r_0 into a and r0, s_1, r_1 into b, t_0 into prev and first.
GARMCAP_MVC_CLONES void firstEdge(Eigen::Index m, const double* __restrict px,
                                  const double* __restrict py, double v0x, double v0y, double v1x,
                                  double v1y, Scratch& __restrict s) {
  for (Eigen::Index k = 0; k < m; ++k) {
    const double ax = v0x - px[k], ay = v0y - py[k];
    const double bx = v1x - px[k], by = v1y - py[k];
    const double r0 = std::sqrt(ax * ax + ay * ay);
    const double r1 = std::sqrt(bx * bx + by * by);
    s.sxa[k] = ax;
    s.sya[k] = ay;
    s.ra[k] = r0;
    s.r0[k] = r0;
    s.sxb[k] = bx;
    s.syb[k] = by;
    s.rb[k] = r1;
    const HalfAngle t = halfAngleFraction(ax, ay, r0, bx, by, r1);
    s.numPrev[k] = t.num;
    s.denPrev[k] = t.den;
    s.numFirst[k] = t.num;
    s.denFirst[k] = t.den;
    s.sum[k] = 0;
  }
}

// Edge i -> i+1 (vertex i+1 at v): reads s_i, r_i from a and t_{i-1} from prev, writes
// s_{i+1}, r_{i+1} into b, t_i into prev, and column i (stride: the block's rows of it).
GARMCAP_MVC_CLONES void edgeColumn(Eigen::Index m, const double* __restrict px,
                                   const double* __restrict py, double vx, double vy,
                                   const double* __restrict sxa, const double* __restrict sya,
                                   const double* __restrict ra, double* __restrict sxb,
                                   double* __restrict syb, double* __restrict rb,
                                   double* __restrict numPrev, double* __restrict denPrev,
                                   double* __restrict col, double* __restrict sum) {
  for (Eigen::Index k = 0; k < m; ++k) {
    const double bx = vx - px[k], by = vy - py[k];
    const double rn = std::sqrt(bx * bx + by * by);
    sxb[k] = bx;
    syb[k] = by;
    rb[k] = rn;
    const HalfAngle t = halfAngleFraction(sxa[k], sya[k], ra[k], bx, by, rn);
    const double w = (numPrev[k] * t.den + t.num * denPrev[k]) / (denPrev[k] * t.den * ra[k]);
    col[k] = w;
    sum[k] += w;
    numPrev[k] = t.num;
    denPrev[k] = t.den;
  }
}

// Closes the ring, column 0 = (t_{n-1} + t_0) / r_0, then normalises the block's rows of
// every column; sum becomes 1/Σw.
GARMCAP_MVC_CLONES void closeAndNormalise(Eigen::Index m, Eigen::Index n, Eigen::Index stride,
                                          Scratch& __restrict s, double* __restrict weights) {
  for (Eigen::Index k = 0; k < m; ++k) {
    const double w = (s.numPrev[k] * s.denFirst[k] + s.numFirst[k] * s.denPrev[k]) /
                     (s.denPrev[k] * s.denFirst[k] * s.r0[k]);
    weights[k] = w;
    s.sum[k] = 1.0 / (s.sum[k] + w);
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    double* __restrict col = weights + i * stride;
    for (Eigen::Index k = 0; k < m; ++k)
      col[k] *= s.sum[k];
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
  Scratch s;
  // Blocks of points: every pass over the edges then works on L1-resident scratch and on a
  // block of the weight columns, instead of streaming all points' arrays once per edge.
  for (Eigen::Index b0 = 0; b0 < m; b0 += kBlock) {
    const Eigen::Index mb = std::min(kBlock, m - b0);
    double* sxa = s.sxa;
    double* sya = s.sya;
    double* ra = s.ra;
    double* sxb = s.sxb;
    double* syb = s.syb;
    double* rb = s.rb;
    firstEdge(mb, px + b0, py + b0, polygon(0, 0), polygon(0, 1), polygon(1, 0), polygon(1, 1), s);
    // Edges 1 .. n-1; edge n-1 wraps to vertex 0, whose s and r are recomputed into b
    // (cheaper than a special loop, and bit-identical).
    for (Eigen::Index i = 1; i < n; ++i) {
      const Eigen::Index j = (i + 1) % n;
      edgeColumn(mb, px + b0, py + b0, polygon(j, 0), polygon(j, 1), sxb, syb, rb, sxa, sya, ra,
                 s.numPrev, s.denPrev, weights.col(i).data() + b0, s.sum);
      std::swap(sxa, sxb);
      std::swap(sya, syb);
      std::swap(ra, rb);
    }
    closeAndNormalise(mb, n, m, s, weights.data() + b0);
    // Rows whose sum was not a finite non-zero number are the special points: on a vertex or
    // an edge, or with overflowing weights. sum now holds 1/Σw.
    for (Eigen::Index k = 0; k < mb; ++k) {
      if (!std::isfinite(s.sum[k]) || s.sum[k] == 0) {
        if (auto problem = exactRow(polygon, px[b0 + k], py[b0 + k], b0 + k, weights))
          return problem;
      }
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
