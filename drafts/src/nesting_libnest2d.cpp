// libnest2d behind a standard-types interface; see nesting_libnest2d.h (compiled as C++17).
#include "nesting_libnest2d.h"

#include <algorithm>
#include <cmath>
#include <libnest2d/libnest2d.hpp>
#include <stdexcept>

namespace garmcap::drafts::detail {
namespace {

// libnest2d's clipper backend works in integers: 1 unit = 1 micrometre.
constexpr double kUnitsPerCm = 10000.0;

ClipperLib::cInt units(double cm) {
  return static_cast<ClipperLib::cInt>(std::llround(cm * kUnitsPerCm));
}

}  // namespace

std::vector<NestPlacement> nestInStrip(const std::vector<NestRing>& rings, double widthCm,
                                       double gapCm) {
  using namespace libnest2d;
  std::vector<Item> items;
  items.reserve(rings.size());
  double totalLength = 0;
  for (const auto& ring : rings) {
    if (ring.size() < 3)
      throw std::runtime_error("nesting: a piece outline has fewer than 3 points");
    PolygonImpl poly;
    for (const auto& [x, y] : ring)
      poly.Contour.push_back({units(x), units(y)});
    poly.Contour.push_back(poly.Contour.front());  // libnest2d wants closed contours
    // The clipper backend's contours turn clockwise (negative area in y-up coordinates).
    if (ClipperLib::Orientation(poly.Contour))
      std::reverse(poly.Contour.begin(), poly.Contour.end());
    double minX = 1e300, maxX = -1e300, minY = 1e300, maxY = -1e300;
    for (const auto& [x, y] : ring) {
      minX = std::min(minX, x);
      maxX = std::max(maxX, x);
      minY = std::min(minY, y);
      maxY = std::max(maxY, y);
    }
    if (maxY - minY > widthCm)
      throw std::runtime_error("nesting: a piece is " + std::to_string(maxY - minY) +
                               " cm across the grain, wider than the fabric (" +
                               std::to_string(widthCm) + " cm)");
    totalLength += maxX - minX + 2 * gapCm;
    // libnest2d 5.0's clipper backend implements only the no-fit polygon of two CONVEX shapes
    // (MaxNfpLevel = CONVEX_ONLY; given concave ones it returns a wrong NFP and pieces overlap),
    // so pieces are nested by their convex hulls, as Cura and PrusaSlicer use it.
    items.emplace_back(sl::convexHull(poly));
  }
  NestConfig<NfpPlacer, FirstFitSelection> cfg;
  cfg.placer_config.rotations = {Radians(0.0), Radians(Pi)};
  cfg.placer_config.alignment = NfpPlacer::Config::Alignment::BOTTOM_LEFT;
  cfg.placer_config.starting_point = NfpPlacer::Config::Alignment::BOTTOM_LEFT;
  cfg.placer_config.accuracy = 0.65f;
  cfg.placer_config.parallel = false;  // the station's two cores are shared
  // libnest2d packs into a fixed box (its default score keeps the pile compact) and opens a
  // new box for what does not fit. A strip is packed by shrinking the box: start at the
  // shortest length that could hold the pieces' hulls (their area over the width, and the
  // longest piece) and lengthen it by 4 % until every piece fits in one box.
  double hullArea = 0, longest = 0;
  for (const auto& item : items) {
    hullArea += static_cast<double>(sl::area(item.rawShape())) / (kUnitsPerCm * kUnitsPerCm);
    const auto bb = sl::boundingBox(item.rawShape());
    longest = std::max(
        longest, static_cast<double>(getX(bb.maxCorner()) - getX(bb.minCorner())) / kUnitsPerCm);
  }
  double length = std::max(longest + 2 * gapCm, std::abs(hullArea) / widthCm);
  for (;; length *= 1.04) {
    if (length > totalLength + 1.0)
      length = totalLength + 1.0;  // one row always fits
    const Box strip({0, 0}, {units(length), units(widthCm)});
    std::vector<Item> trial = items;
    const std::size_t bins = nest(trial, strip, units(gapCm), cfg);
    bool one = bins == 1;
    for (const auto& item : trial)
      one = one && item.binId() == 0;
    if (one) {
      items = std::move(trial);
      break;
    }
    if (length >= totalLength + 1.0)
      throw std::runtime_error("nesting: the pieces did not fit in one strip (" +
                               std::to_string(bins) + " bins)");
  }
  std::vector<NestPlacement> out;
  for (const auto& item : items) {
    const auto t = item.translation();
    out.push_back(
        {static_cast<double>(item.rotation()), getX(t) / kUnitsPerCm, getY(t) / kUnitsPerCm});
  }
  return out;
}

}  // namespace garmcap::drafts::detail
