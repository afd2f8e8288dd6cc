// Cut lines with seam allowance; see seam_allowance.h.
#include "garmcap/drafts/seam_allowance.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "export_util.h"
#include "garmcap/drafts/geometry.h"
#include "garmcap/drafts/panel_edges.h"

namespace garmcap::drafts {
namespace {

constexpr double kMiterLimit = 4.0;    // mitre length / allowance beyond which a corner is bevelled
constexpr double kLowestTieCm = 0.01;  // vertices this close to the lowest y are all "lowest"
constexpr double kHemCornerDeg = 45.0;  // a sharper turn ends the hem
constexpr double kParallelSin = 1e-3;   // edges this close to parallel meet in a step, not a mitre

int wrap(int i, int n) {
  return ((i % n) + n) % n;
}

// A dart opened in the outline: edges first .. first+count-1 run from one leg down to the apex
// and back up to the other leg.
struct DartRun {
  int first = 0;
  int count = 0;
};

std::vector<DartRun> dartRuns(const Panel& panel) {
  const auto& o = panel.outline;
  const int n = static_cast<int>(o.size());
  std::vector<DartRun> runs;
  for (const auto& d : panel.darts) {
    const int i1 = detail::nearestVertex(o, d.leg1);
    const int i2 = detail::nearestVertex(o, d.leg2);
    if (i1 < 0 || i2 < 0 || i1 == i2)
      continue;  // a dart drawn inside the piece, not opened in its outline
    const int forward = wrap(i2 - i1, n);
    const int backward = n - forward;
    DartRun r{forward <= backward ? i1 : i2, std::min(forward, backward)};
    const int apex = detail::nearestVertex(o, d.apex);
    if (r.count < 2 || apex < 0 || wrap(apex - r.first, n) == 0 ||
        wrap(apex - r.first, n) >= r.count)
      continue;  // the outline runs past the dart (drawn on the piece): nothing opened
    runs.push_back(r);
  }
  return runs;
}

Point2 outwardNormal(const Point2& a, const Point2& b, bool positiveArea) {
  const Point2 e = (b - a).normalized();
  // Positive shoelace area: the interior lies to the left of each edge, (-ey, ex).
  return positiveArea ? Point2(e.y(), -e.x()) : Point2(-e.y(), e.x());
}

// Removes the small loops an outward offset makes where short edges turn sharply inward (a
// concave curve sampled finely): each pair of crossing edges within half the polygon is
// joined at its crossing and the loop between them dropped.
Polyline withoutLoops(Polyline p) {
  bool changed = true;
  while (changed && p.size() > 3) {
    changed = false;
    const int n = static_cast<int>(p.size());
    for (int i = 0; i < n && !changed; ++i) {
      const Point2& a0 = p[static_cast<size_t>(i)];
      const Point2& a1 = p[static_cast<size_t>(wrap(i + 1, n))];
      for (int k = 2; k <= n / 2 && !changed; ++k) {
        const int j = wrap(i + k, n);
        if (wrap(j + 1, n) == i)
          continue;  // adjacent through the wrap
        auto x = intersectSegments(a0, a1, p[static_cast<size_t>(j)],
                                   p[static_cast<size_t>(wrap(j + 1, n))]);
        if (!x)
          continue;
        // Keep edge i up to the crossing, then edge j from it: drop vertices i+1 .. j.
        Polyline q;
        q.reserve(p.size());
        for (int m = 0; m < n; ++m) {
          const int pos = wrap(m - (i + 1), n);  // 0 for vertex i+1
          if (pos < k)
            continue;
          q.push_back(p[static_cast<size_t>(m)]);
          if (m == i)
            q.push_back(*x);
        }
        p = std::move(q);
        changed = true;
      }
    }
  }
  return p;
}

Line mirroredLine(const Line& l, const Line& axis) {
  const Point2 o = mirrorPoint(l.origin, axis);
  return Line{o, mirrorPoint(l.origin + l.direction, axis) - o};
}

Point2 rotated(const Point2& p, const Point2& pivot, double c, double s) {
  const Point2 d = p - pivot;
  return pivot + Point2(c * d.x() - s * d.y(), s * d.x() + c * d.y());
}

// The cut line across a dart opened in the outline, as a pattern maker finds it: close the
// dart (the outline after it turned about the apex until its leg lies on the first leg), cut
// the closed seam line's allowance, and unfold. `before` / `after` are the offset lines of
// the edges that end at the first leg `leg1At` / start at the second leg `leg2At`. The intake
// is pressed toward the first leg, so its half next to that leg lies mirrored over the piece
// there and is cut with it, and its other half, folded again on the dart's centre line,
// mirrors that once more. Appends the cut points from the first leg's side to the second's;
// false when the legs are parallel to each other or to the edges beside them.
bool appendDartCap(Polyline& out, const Line& before, const Line& after, const Point2& leg1At,
                   const Point2& leg2At, const Line& leg1, const Line& leg2,
                   const Point2& outward) {
  const auto apex = intersectLines(leg1, leg2);
  if (!apex)
    return false;
  const Point2 u1 = (leg1At - *apex).normalized(), u2 = (leg2At - *apex).normalized();
  // Rotation about the apex taking the second leg onto the first, and back.
  const double c = u2.dot(u1), s = cross2d(u2, u1);
  const Line afterClosed{
      rotated(after.origin, *apex, c, s),
      rotated(after.origin + after.direction, *apex, c, s) - rotated(after.origin, *apex, c, s)};
  const auto m = intersectLines(before, afterClosed);  // the closed seam's cut corner
  if (!m)
    return false;
  // Which side of the first leg the corner falls on: the piece before the dart, or the intake
  // (where, closed, the piece after the dart lies).
  const double intakeSide = cross2d(u1, u2);
  const bool cornerBeforeLeg = cross2d(u1, *m - *apex) * intakeSide < 0;
  // The closed cut line on the first piece's side, ending where it crosses the first leg.
  Polyline firstSide;
  if (cornerBeforeLeg) {
    const auto cross = intersectLines(afterClosed, leg1);
    if (!cross)
      return false;
    firstSide = {*m, *cross};
  } else {
    const auto cross = intersectLines(before, leg1);
    if (!cross)
      return false;
    firstSide = {*cross};
  }
  // Half the intake: that cut mirrored about the first leg, up to the dart's centre line.
  const Line centre{*apex, u1 + u2};
  Polyline half{firstSide.back()};
  const Point2 legCross = firstSide.back();
  std::optional<Point2> onCentre;
  if (cornerBeforeLeg) {
    const Point2 mm = mirrorPoint(*m, leg1);
    const auto hit = intersectLines(Line{legCross, mm - legCross}, centre);
    if (hit && (*hit - legCross).dot(mm - legCross) <= (mm - legCross).squaredNorm()) {
      onCentre = hit;
    } else {
      half.push_back(mm);
      onCentre = intersectLines(mirroredLine(before, leg1), centre);
    }
  } else {
    onCentre = intersectLines(mirroredLine(before, leg1), centre);
  }
  // Legs that open toward the edge give a cap pointing out; legs that close toward it (the
  // high-waist skirt's at its top line continue the bodice darts above) one pointing in, a
  // shallow V between the legs. Beyond the legs' meeting point there is no cap.
  const Point2 centreOut = (u1 + u2).dot(outward) >= 0 ? Point2(u1 + u2) : Point2(-(u1 + u2));
  if (!onCentre || (*onCentre - *apex).dot(centreOut) * (legCross - *apex).dot(centreOut) <= 0)
    return false;
  half.push_back(*onCentre);
  // Out: the first side, the mirrored half, the other half (mirrored about the centre line,
  // back to the second leg), then on the second piece's side the closed cut turned back.
  for (const auto& p : firstSide)
    out.push_back(p);
  for (size_t k = 1; k < half.size(); ++k)
    out.push_back(half[k]);
  for (size_t k = half.size() - 1; k-- > 0;)
    out.push_back(mirrorPoint(half[k], centre));
  if (!cornerBeforeLeg)
    out.push_back(rotated(*m, *apex, c, -s));
  return true;
}

// x of the piece's centre line: its fold, else the centre seam that joins it to its own
// mirrored twin (a skirt back cut twice); std::nullopt when neither is a vertical line.
std::optional<double> centreLineX(const Panel& panel, const Pattern& pattern) {
  const auto& o = panel.outline;
  if (auto fold = foldEdge(panel, pattern))
    return o[static_cast<size_t>(fold->from)].x();
  for (const auto& s : pattern.seams) {
    if (s.a.panel != panel.name || !seamJoinsTwins(s))
      continue;
    const Point2& from = o[static_cast<size_t>(s.a.from)];
    const Point2& to = o[static_cast<size_t>(s.a.to)];
    if (std::abs(from.x() - to.x()) < 0.2 * std::abs(from.y() - to.y()))
      return (from.x() + to.x()) / 2;
  }
  return std::nullopt;
}

// Which way a pattern maker presses a dart's intake: a vertical dart toward the centre line,
// a horizontal one (a bust dart from the side or armhole) down; toward the first leg along the
// outline when the piece has no centre line.
bool pressTowardFirstLeg(const Point2& leg1At, const Point2& leg2At, const Line& leg1,
                         const Line& leg2, std::optional<double> centreX) {
  const auto apex = intersectLines(leg1, leg2);
  if (!apex)
    return true;
  const Point2 centreDir = (leg1At - *apex).normalized() + (leg2At - *apex).normalized();
  if (std::abs(centreDir.x()) > std::abs(centreDir.y()))
    return leg1At.y() >= leg2At.y();  // horizontal: the lower leg (y down)
  if (!centreX)
    return true;
  return std::abs(leg1At.x() - *centreX) <= std::abs(leg2At.x() - *centreX);
}

}  // namespace

const char* edgeRoleName(EdgeRole role) {
  switch (role) {
    case EdgeRole::Seam:
      return "seam";
    case EdgeRole::Free:
      return "free";
    case EdgeRole::Hem:
      return "hem";
    case EdgeRole::Fold:
      return "fold";
    case EdgeRole::Dart:
      return "dart";
  }
  return "?";
}

Polyline dartPath(const Panel& panel, const Dart& dart) {
  Panel one = panel;
  one.darts = {dart};
  const auto runs = dartRuns(one);
  if (runs.empty())
    return {dart.leg1, dart.apex, dart.leg2};
  const int n = static_cast<int>(panel.outline.size());
  Polyline path;
  for (int k = 0; k <= runs[0].count; ++k)
    path.push_back(panel.outline[static_cast<size_t>(wrap(runs[0].first + k, n))]);
  return path;
}

std::vector<EdgeRole> edgeRoles(const Panel& panel, const Pattern& pattern) {
  const auto& o = panel.outline;
  const int n = static_cast<int>(o.size());
  std::vector<EdgeRole> roles(static_cast<size_t>(n), EdgeRole::Free);
  for (const auto& s : pattern.seams)
    for (const auto* e : {&s.a, &s.b})
      if (e->panel == panel.name)
        for (int i = 0; i < n; ++i)
          if (edgeInside(*e, i, n))
            roles[static_cast<size_t>(i)] = EdgeRole::Seam;
  if (auto fold = foldEdge(panel, pattern))
    for (int i = 0; i < n; ++i)
      if (edgeInside(*fold, i, n))
        roles[static_cast<size_t>(i)] = EdgeRole::Fold;
  for (const auto& r : dartRuns(panel))
    for (int k = 0; k < r.count; ++k)
      roles[static_cast<size_t>(wrap(r.first + k, n))] = EdgeRole::Dart;

  // The hem: the run of free edges that holds the piece's lowest vertex (largest y).
  double maxY = -1e300;
  for (const auto& p : o)
    maxY = std::max(maxY, p.y());
  auto P = [&](int i) { return o[static_cast<size_t>(wrap(i, n))]; };
  auto isFree = [&](int i) { return roles[static_cast<size_t>(wrap(i, n))] == EdgeRole::Free; };
  for (int v = 0; v < n; ++v) {
    if (o[static_cast<size_t>(v)].y() < maxY - kLowestTieCm)
      continue;
    const int seed = isFree(v) ? v : isFree(v - 1) ? v - 1 : -1;
    if (seed < 0)
      continue;
    // The hem ends at a corner: a free run may go on round it (up a side left unsewn).
    auto smoothAt = [&](int vertex) {
      const Point2 in = P(vertex) - P(vertex - 1), out = P(vertex + 1) - P(vertex);
      if (in.norm() < kGeometryEpsCm || out.norm() < kGeometryEpsCm)
        return true;
      return in.normalized().dot(out.normalized()) > std::cos(kHemCornerDeg * kPi / 180.0);
    };
    // Darts opened in the hem (a bodice's waist) interrupt the run, not the hem.
    auto isDart = [&](int i) { return roles[static_cast<size_t>(wrap(i, n))] == EdgeRole::Dart; };
    int lo = seed, hi = seed;
    for (int guard = 0; guard < n; ++guard) {
      int k = lo - 1;
      while (isDart(k) && k > lo - n)
        --k;
      if (!isFree(k) || wrap(k, n) == wrap(hi, n) || (k == lo - 1 && !smoothAt(lo)))
        break;
      lo = k;
    }
    for (int guard = 0; guard < n; ++guard) {
      int k = hi + 1;
      while (isDart(k) && k < hi + n)
        ++k;
      if (!isFree(k) || wrap(k, n) == wrap(lo, n) || (k == hi + 1 && !smoothAt(hi + 1)))
        break;
      hi = k;
    }
    for (int i = lo; i <= hi; ++i)
      if (isFree(i))
        roles[static_cast<size_t>(wrap(i, n))] = EdgeRole::Hem;
    break;
  }
  return roles;
}

std::vector<double> edgeAllowances(const Panel& panel, const Pattern& pattern) {
  std::vector<double> out;
  for (EdgeRole r : edgeRoles(panel, pattern)) {
    switch (r) {
      case EdgeRole::Seam:
      case EdgeRole::Free:
        out.push_back(panel.seamAllowanceCm);
        break;
      case EdgeRole::Hem:
        out.push_back(kHemAllowanceCm);
        break;
      case EdgeRole::Fold:
      case EdgeRole::Dart:
        out.push_back(0.0);
        break;
    }
  }
  return out;
}

Polyline cutOutline(const Panel& panel, const Pattern& pattern) {
  detail::checkPanel<SeamAllowanceError>(panel);
  const auto& o = panel.outline;
  const int n = static_cast<int>(o.size());
  if (findSelfIntersection(o))
    throw SeamAllowanceError("panel '" + panel.name + "': outline crosses itself, no cut line");
  const std::vector<EdgeRole> roles = edgeRoles(panel, pattern);
  const std::vector<double> dist = edgeAllowances(panel, pattern);
  const bool positive = signedArea(o) > 0;
  const double orientation = positive ? 1.0 : -1.0;

  auto P = [&](int i) { return o[static_cast<size_t>(wrap(i, n))]; };
  auto edgeLen = [&](int i) { return (P(i + 1) - P(i)).norm(); };
  const std::optional<double> centreX = centreLineX(panel, pattern);
  auto normal = [&](int i) { return outwardNormal(P(i), P(i + 1), positive); };
  auto offsetLine = [&](int i) {
    return Line{P(i) + dist[static_cast<size_t>(wrap(i, n))] * normal(i), P(i + 1) - P(i)};
  };
  auto fail = [&](const std::string& why) {
    return SeamAllowanceError("panel '" + panel.name + "': no cut line, " + why);
  };
  // Previous / next edge of non-zero length (repeated vertices are skipped).
  auto prevEdge = [&](int i) {
    int k = i - 1;
    while (edgeLen(k) < kGeometryEpsCm && wrap(k, n) != wrap(i, n))
      --k;
    return k;
  };

  Polyline raw;
  // A hem corner, trued as a pattern maker does: the side edge's cut line runs on to the hem
  // line and then turns as its mirror image about the hem line, so that the hem allowance,
  // turned up, lies flat against the side seam of a flared or tapered piece. false when the
  // corner is no hem corner (or too flat to be one).
  auto trueHemCorner = [&](int a, int b, int v) {
    const EdgeRole ra = roles[static_cast<size_t>(wrap(a, n))];
    const EdgeRole rb = roles[static_cast<size_t>(wrap(b, n))];
    auto isSide = [](EdgeRole r) { return r == EdgeRole::Seam || r == EdgeRole::Free; };
    const bool hemAfter = rb == EdgeRole::Hem && isSide(ra);
    const bool hemBefore = ra == EdgeRole::Hem && isSide(rb);
    if (!hemAfter && !hemBefore)
      return false;
    const Point2 ua = (P(a + 1) - P(a)).normalized(), ub = (P(b + 1) - P(b)).normalized();
    if (ua.dot(ub) > std::cos(kHemCornerDeg * kPi / 180.0))
      return false;
    const int hem = hemAfter ? b : a, side = hemAfter ? a : b;
    const auto hemLine = Line::through(P(hem), P(hem + 1));
    if (!hemLine)
      return false;
    const Line sideCut = offsetLine(side);
    const auto onHemLine = intersectLines(sideCut, *hemLine);
    const auto turned = intersectLines(mirroredLine(sideCut, *hemLine), offsetLine(hem));
    const double reach =
        4 * (dist[static_cast<size_t>(wrap(a, n))] + dist[static_cast<size_t>(wrap(b, n))]);
    if (!onHemLine || !turned || (*onHemLine - P(v)).norm() > reach ||
        (*turned - P(v)).norm() > reach)
      return false;
    if (std::abs(ua.dot(ub)) < 1e-9) {
      raw.push_back(*turned);  // a side square to the hem is its own mirror image: the mitre
      return true;
    }
    raw.push_back(hemAfter ? *onHemLine : *turned);
    raw.push_back(hemAfter ? *turned : *onHemLine);
    return true;
  };
  // Where edges a (ending at vertex v) and b (starting at v) meet, offset by their allowances.
  auto join = [&](int a, int b, int v) {
    if (trueHemCorner(a, b, v))
      return;
    const double da = dist[static_cast<size_t>(wrap(a, n))];
    const double db = dist[static_cast<size_t>(wrap(b, n))];
    const Point2 ua = (P(a + 1) - P(a)).normalized(), ub = (P(b + 1) - P(b)).normalized();
    const Point2 pa = P(v) + da * normal(a), pb = P(v) + db * normal(b);
    const double turn = cross2d(ua, ub) * orientation;  // > 0: convex corner
    if (std::abs(turn) < kParallelSin && ua.dot(ub) > 0) {
      raw.push_back(pa);  // straight on: one point, or a step where the allowance changes
      if ((pb - pa).norm() > kGeometryEpsCm)
        raw.push_back(pb);
      return;
    }
    const auto miter = intersectLines(offsetLine(a), offsetLine(b));
    const double limit = kMiterLimit * std::max(da, db);
    if (miter && (turn < 0 || (*miter - P(v)).norm() <= limit)) {
      raw.push_back(*miter);
    } else {
      raw.push_back(pa);
      if ((pb - pa).norm() > kGeometryEpsCm)
        raw.push_back(pb);
    }
  };

  for (int v = 0; v < n; ++v) {
    const int b = v;  // the edge starting at v
    if (edgeLen(b) < kGeometryEpsCm)
      continue;
    const int a = prevEdge(v);
    const EdgeRole ra = roles[static_cast<size_t>(wrap(a, n))];
    const EdgeRole rb = roles[static_cast<size_t>(wrap(b, n))];
    if (rb != EdgeRole::Dart && ra != EdgeRole::Dart) {
      join(a, b, v);
      continue;
    }
    if (ra == EdgeRole::Dart)
      continue;  // inside the dart or at its closing leg: written with the cap
    // v is the first leg of a dart opened in the outline: find its closing leg.
    int last = v;
    while (roles[static_cast<size_t>(wrap(last, n))] == EdgeRole::Dart && last < v + n)
      ++last;
    const int closing = last;  // vertex of the second leg; edge `closing` leaves the dart
    const auto leg1 = Line::through(P(v), P(v + 1));
    const auto leg2 = Line::through(P(closing), P(closing - 1));
    if (!leg1 || !leg2)
      throw fail("a dart leg has zero length");
    // Pressed toward the first leg, or the cap of the walk reversed: pressed toward the second.
    bool capped = false;
    if (pressTowardFirstLeg(P(v), P(closing), *leg1, *leg2, centreX)) {
      capped = appendDartCap(raw, offsetLine(a), offsetLine(closing), P(v), P(closing), *leg1,
                             *leg2, normal(a) + normal(closing));
    } else {
      Polyline cap;
      capped = appendDartCap(cap, offsetLine(closing), offsetLine(a), P(closing), P(v), *leg2,
                             *leg1, normal(a) + normal(closing));
      raw.insert(raw.end(), cap.rbegin(), cap.rend());
    }
    if (!capped)
      throw fail(
          "no dart cap (the dart's legs are parallel to each other or to the edges "
          "beside it)");
  }

  Polyline cut = withoutLoops(raw);
  if (!isSimplePolygon(cut))
    throw fail("the offset outline crosses itself");
  for (const auto& p : o) {
    const bool onCut = closestPoint(joined(cut, Polyline{cut.front()}), p).distance < 1e-6;
    if (!onCut && !pointInPolygon(p, cut))
      throw fail("the offset outline does not enclose the net outline");
  }
  return cut;
}

}  // namespace garmcap::drafts
