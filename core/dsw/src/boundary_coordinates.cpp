#include "boundary_coordinates.h"

#include <cmath>

namespace garmcap::dsw {

Eigen::Index exactBoundaryLocation(const Points& polygon, double x, double y, Eigen::Index& vertex,
                                   double& t) {
  const Eigen::Index n = polygon.rows();
  vertex = -1;
  t = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (polygon(i, 0) == x && polygon(i, 1) == y) {
      vertex = i;
      return -1;
    }
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index j = (i + 1) % n;
    const double sxi = polygon(i, 0) - x, syi = polygon(i, 1) - y;
    const double sxj = polygon(j, 0) - x, syj = polygon(j, 1) - y;
    const double det = sxi * syj - syi * sxj;
    const double dot = sxi * sxj + syi * syj;
    if (det == 0 && dot < 0) {
      const double ri = std::hypot(sxi, syi);
      const double rj = std::hypot(sxj, syj);
      t = ri / (ri + rj);
      return i;
    }
  }
  return -1;
}

}  // namespace garmcap::dsw
