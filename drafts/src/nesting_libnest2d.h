#pragma once
// Private: the one unit that includes libnest2d (Debian's libnest2d-dev 5.0, header-only, with
// its clipper geometry backend and NLopt optimizers). libnest2d 5.0's headers do not compile as
// C++20 (an ambiguous Radians != Radians under C++20's reversed comparison operators), so this
// unit is compiled as C++17 and its interface holds standard types only.

#include <string>
#include <utility>
#include <vector>

namespace garmcap::drafts::detail {

/// Where the nester put one shape: rotate about the origin by `rotationRad` (0 or pi), then
/// translate by (dx, dy). Units as given (cm).
struct NestPlacement {
  double rotationRad = 0;
  double dx = 0, dy = 0;
};

/// Closed rings (first point not repeated), cm, x along the strip, y across it.
using NestRing = std::vector<std::pair<double, double>>;

/// Places every ring in the strip 0 <= y <= widthCm, x >= 0, turning a ring only by 0 or 180
/// degrees, at least `gapCm` apart, packed toward x = 0: libnest2d's no-fit-polygon placer with
/// first-fit selection packs the rings' convex hulls into a box of the strip's width whose
/// length starts at the hulls' area over the width and grows by 4 % until all fit in one box.
/// Throws std::runtime_error when a ring is wider than the strip (no turn allowed makes it fit).
std::vector<NestPlacement> nestInStrip(const std::vector<NestRing>& rings, double widthCm,
                                       double gapCm);

}  // namespace garmcap::drafts::detail
