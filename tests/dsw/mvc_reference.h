#pragma once
// Long-double reference mean value coordinates for the tests and the benchmark: the
// Hormann-Floater formula evaluated point by point in 80-bit extended precision, with exact
// vertex and edge cases. Used where CGAL 5.5 is not sound (queries within 1e-3 cm of an edge's
// line, where its PRECISE policy loses digits and its FAST policies return NaN).

#include <cmath>
#include <vector>

#include "garmcap/dsw/polygon.h"

namespace garmcap::dsw::testing {

inline Eigen::MatrixXd referenceMvc(const Points& cage, const Points& pts) {
  using LD = long double;
  const Eigen::Index n = cage.rows();
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(pts.rows(), n);
  std::vector<LD> sx(static_cast<std::size_t>(n)), sy(sx.size()), r(sx.size()), t(sx.size());
  for (Eigen::Index k = 0; k < pts.rows(); ++k) {
    const LD x = pts(k, 0), y = pts(k, 1);
    bool done = false;
    for (Eigen::Index i = 0; i < n && !done; ++i) {
      const auto u = static_cast<std::size_t>(i);
      sx[u] = cage(i, 0) - x;
      sy[u] = cage(i, 1) - y;
      r[u] = std::sqrt(sx[u] * sx[u] + sy[u] * sy[u]);
      if (r[u] == 0) {
        out(k, i) = 1;
        done = true;
      }
    }
    if (done)
      continue;
    for (std::size_t i = 0; i < sx.size() && !done; ++i) {
      const std::size_t j = (i + 1) % sx.size();
      const LD det = sx[i] * sy[j] - sy[i] * sx[j];
      const LD dot = sx[i] * sx[j] + sy[i] * sy[j];
      if (det == 0 && dot < 0) {
        out(k, static_cast<Eigen::Index>(i)) = static_cast<double>(r[j] / (r[i] + r[j]));
        out(k, static_cast<Eigen::Index>(j)) = static_cast<double>(r[i] / (r[i] + r[j]));
        done = true;
        break;
      }
      t[i] = dot >= 0 ? det / (r[i] * r[j] + dot) : (r[i] * r[j] - dot) / det;
    }
    if (done)
      continue;
    std::vector<LD> w(sx.size());
    LD sum = 0;
    for (std::size_t i = 0; i < w.size(); ++i) {
      w[i] = (t[(i + w.size() - 1) % w.size()] + t[i]) / r[i];
      sum += w[i];
    }
    for (std::size_t i = 0; i < w.size(); ++i)
      out(k, static_cast<Eigen::Index>(i)) = static_cast<double>(w[i] / sum);
  }
  return out;
}

/// Distance from q to the nearest supporting line of a cage edge.
inline double distanceToEdgeLines(const Points& cage, const Eigen::RowVector2d& q) {
  double best = INFINITY;
  for (Eigen::Index i = 0; i < cage.rows(); ++i) {
    const Eigen::RowVector2d a = cage.row(i), b = cage.row((i + 1) % cage.rows());
    const Eigen::RowVector2d e = b - a;
    const double len = e.norm();
    if (len == 0)
      continue;
    best = std::min(best, std::abs(e.x() * (q.y() - a.y()) - e.y() * (q.x() - a.x())) / len);
  }
  return best;
}

}  // namespace garmcap::dsw::testing
