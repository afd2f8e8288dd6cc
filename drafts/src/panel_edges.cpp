// Seam directions and fold edges of panels; see panel_edges.h.
#include "garmcap/drafts/panel_edges.h"

#include <cmath>

namespace garmcap::drafts {
namespace {
constexpr double kOnLineCm = 0.001;
}  // namespace

bool seamRunsSameWay(const SeamPair& seam) {
  return seam.name == "armhole_front" || seam.name == "armhole_back" || seam.name == "outseam" ||
         seam.name == "inseam";
}

bool seamJoinsTwins(const SeamPair& seam) {
  return seam.a.panel == seam.b.panel && seam.a.from == seam.b.from && seam.a.to == seam.b.to;
}

bool edgeInside(const EdgeRef& e, int i, int vertexCount) {
  const int n = vertexCount;
  const int len = ((e.to - e.from) % n + n) % n;
  const int pos = ((i - e.from) % n + n) % n;
  return pos < len;
}

std::optional<EdgeRef> foldEdge(const Panel& panel, const Pattern& pattern) {
  if (!panel.cutOnFold || panel.outline.size() < 3)
    return std::nullopt;
  const auto& o = panel.outline;
  const int n = static_cast<int>(o.size());
  double minX = o[0].x(), maxX = o[0].x();
  for (const auto& p : o) {
    minX = std::min(minX, p.x());
    maxX = std::max(maxX, p.x());
  }
  auto inSeam = [&](int i) {
    for (const auto& s : pattern.seams)
      for (const auto* e : {&s.a, &s.b})
        if (e->panel == panel.name && edgeInside(*e, i, n))
          return true;
    return false;
  };
  std::optional<EdgeRef> best;
  double bestLen = 0;
  for (double x : {minX, maxX}) {
    auto onLine = [&](int i) {
      const Point2& a = o[static_cast<size_t>(i)];
      const Point2& b = o[static_cast<size_t>((i + 1) % n)];
      return std::abs(a.x() - x) < kOnLineCm && std::abs(b.x() - x) < kOnLineCm && !inSeam(i);
    };
    // Start each run at an edge whose predecessor is not on the line, so runs are maximal.
    for (int i = 0; i < n; ++i) {
      if (!onLine(i) || onLine((i + n - 1) % n))
        continue;
      int j = i;
      double len = 0;
      while (onLine(j) && len < 1e300) {
        len += (o[static_cast<size_t>((j + 1) % n)] - o[static_cast<size_t>(j)]).norm();
        j = (j + 1) % n;
        if (j == i)
          break;
      }
      if (len > bestLen) {
        bestLen = len;
        best = EdgeRef{panel.name, i, j};
      }
    }
  }
  return best;
}

}  // namespace garmcap::drafts
