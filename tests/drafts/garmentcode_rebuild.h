#pragma once
// GarmentCode JSON read back as GarmentCode reads it: each edge evaluated from its endpoints and
// relative control points (control = start + u * (end - start) + v * perp, perp = (-dy, dx), as
// pygarment's rel_to_abs_2d), the loops compared with the garment pieces rebuilt here from the
// drafted panels (unfolded, mirrored, darts as cut-outs). Shared by the drafts tests (every type
// drafted at several sizes) and the dsw tests (every size of every graded size run).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "garmcap/drafts/pattern.h"

namespace garmcap::drafts::rebuild {

using nlohmann::json;

inline Point2 pt(const json& v) {
  return {v[0].get<double>(), v[1].get<double>()};
}

// One GarmentCode edge sampled at `count` + 1 points, evaluated from the file alone.
inline Polyline evalEdge(const json& panel, const json& edge, int count = 40) {
  const Point2 a = pt(panel["vertices"][edge["endpoints"][0].get<size_t>()]);
  const Point2 b = pt(panel["vertices"][edge["endpoints"][1].get<size_t>()]);
  const Point2 d = b - a, perp(-d.y(), d.x());
  auto control = [&](const json& uv) {
    return Point2(a + uv[0].get<double>() * d + uv[1].get<double>() * perp);
  };
  Polyline out;
  for (int k = 0; k <= count; ++k) {
    const double t = static_cast<double>(k) / count, s = 1 - t;
    if (!edge.contains("curvature")) {
      out.push_back(a + t * d);
      continue;
    }
    const auto& c = edge["curvature"];
    const auto& prm = c["params"];
    if (c["type"] == "cubic") {
      const Point2 c1 = control(prm[0]), c2 = control(prm[1]);
      out.push_back(s * s * s * a + 3 * s * s * t * c1 + 3 * s * t * t * c2 + t * t * t * b);
    } else if (c["type"] == "quadratic") {
      const Point2 c1 = control(prm[0]);
      out.push_back(s * s * a + 2 * s * t * c1 + t * t * b);
    } else {
      ADD_FAILURE() << "unexpected curvature type " << c["type"];
      return {};
    }
  }
  return out;
}

inline double length(const Polyline& p) {
  double l = 0;
  for (size_t i = 1; i < p.size(); ++i)
    l += (p[i] - p[i - 1]).norm();
  return l;
}

inline double distToSegments(const Point2& p, const std::vector<std::pair<Point2, Point2>>& segs) {
  double best = 1e300;
  for (const auto& [a, b] : segs) {
    const Point2 ab = b - a;
    const double t =
        ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
    best = std::min(best, (a + t * ab - p).norm());
  }
  return best;
}

// The expected piece (y up) as segments: the drafted outline, unfolded about its centre line
// (the leftmost x of a back, the rightmost of a front) when cut on the fold, mirrored for the
// second of two pieces. Segments on the fold line are dropped (the cloth continues there).
inline std::vector<std::pair<Point2, Point2>> expectedPiece(const Panel& p, bool mirrored) {
  double minX = 1e300, maxX = -1e300;
  for (const auto& q : p.outline) {
    minX = std::min(minX, q.x());
    maxX = std::max(maxX, q.x());
  }
  const double foldX = p.name.find("front") != std::string::npos ? maxX : minX;
  std::vector<std::pair<Point2, Point2>> segs;
  const size_t n = p.outline.size();
  for (size_t i = 0; i < n; ++i) {
    Point2 a = p.outline[i], b = p.outline[(i + 1) % n];
    if (p.cutOnFold && std::abs(a.x() - foldX) < 1e-3 && std::abs(b.x() - foldX) < 1e-3)
      continue;
    a.y() = -a.y();
    b.y() = -b.y();
    if (mirrored) {
      a.x() = -a.x();
      b.x() = -b.x();
    }
    segs.emplace_back(a, b);
    if (p.cutOnFold)
      segs.emplace_back(Point2(2 * foldX - a.x(), a.y()), Point2(2 * foldX - b.x(), b.y()));
  }
  return segs;
}

inline Polyline sampleSegments(const std::vector<std::pair<Point2, Point2>>& segs) {
  Polyline out;
  for (const auto& [a, b] : segs)
    for (int k = 0; k < 10; ++k)
      out.push_back(a + (b - a) * (k / 10.0));
  return out;
}

struct RebuildBounds {
  Point2 min{1e300, 1e300};
  void add(const Point2& p) { min = min.cwiseMin(p); }
};

// The length each garment piece has stitched, from the draft: every seam edge of the panel
// (dart cut-outs inside included: their sides are stitched to each other) and every dart not
// inside a seam, twice for a piece unfolded from a half.
inline double expectedStitchedCm(const Pattern& pat, const Panel& p) {
  const size_t n = p.outline.size();
  auto arc = [&](size_t from, size_t to) {
    double l = 0;
    for (size_t i = from; i != to; i = (i + 1) % n)
      l += (p.outline[(i + 1) % n] - p.outline[i]).norm();
    return l;
  };
  std::vector<bool> covered(n, false);
  double sum = 0;
  for (const auto& s : pat.seams) {
    const bool twins = s.a.panel == s.b.panel && s.a.from == s.b.from && s.a.to == s.b.to;
    for (const auto* e : {&s.a, &s.b}) {
      if (e->panel != p.name || (twins && e == &s.b))
        continue;
      sum += arc(static_cast<size_t>(e->from), static_cast<size_t>(e->to));
      for (size_t i = static_cast<size_t>(e->from); i != static_cast<size_t>(e->to);
           i = (i + 1) % n)
        covered[i] = true;
    }
  }
  auto vertexAt = [&](const Point2& q) {
    for (size_t i = 0; i < n; ++i)
      if ((p.outline[i] - q).norm() < 1e-3)
        return static_cast<long>(i);
    return -1L;
  };
  for (const auto& d : p.darts) {
    const long l1 = vertexAt(d.leg1), ap = vertexAt(d.apex), l2 = vertexAt(d.leg2);
    if (l1 < 0 || ap < 0 || l2 < 0 || covered[static_cast<size_t>(ap)])
      continue;  // inside the piece, or inside a seam (counted with it)
    // The cut-out along the outline, from leg to leg through the apex (which way is shorter).
    const double a = arc(static_cast<size_t>(l1), static_cast<size_t>(l2));
    const double b = arc(static_cast<size_t>(l2), static_cast<size_t>(l1));
    sum += std::min(a, b);
  }
  return p.cutOnFold ? 2 * sum : sum;
}

// The GarmentCode specification `spec` read back and compared with the pattern it was
// written from: loops within 1 mm of the garment pieces, stitches on real edges with matching
// lengths, every seam and dart stitched, lower pieces hung below the bodice. `worst`, when
// given, is raised to the largest distance between a loop and its piece, cm.
inline void checkSpec(const Pattern& pat, const json& spec, double* worst = nullptr) {
  EXPECT_EQ(spec["properties"]["units_in_meter"], 100);
  EXPECT_EQ(spec["properties"]["curvature_coords"], "relative");
  const json& panels = spec["pattern"]["panels"];

  std::map<std::string, std::pair<const Panel*, bool>> want;  // GC name -> panel, mirrored
  for (const auto& p : pat.panels) {
    want[p.name] = {&p, false};
    if (!p.cutOnFold && p.cutCount == 2)
      want[p.name + "_mirrored"] = {&p, true};
  }
  ASSERT_EQ(panels.size(), want.size());

  std::map<std::string, std::vector<Polyline>> curves;
  for (const auto& [name, w] : want) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(panels.contains(name));
    const json& gp = panels[name];
    const auto& edges = gp["edges"];
    ASSERT_GE(edges.size(), 3u);
    Polyline loop;
    double area = 0;
    for (size_t k = 0; k < edges.size(); ++k) {
      // Edges chain into one loop.
      EXPECT_EQ(edges[k]["endpoints"][1], edges[(k + 1) % edges.size()]["endpoints"][0]);
      curves[name].push_back(evalEdge(gp, edges[k]));
      const Point2 a = pt(gp["vertices"][edges[k]["endpoints"][0].get<size_t>()]);
      const Point2 b = pt(gp["vertices"][edges[k]["endpoints"][1].get<size_t>()]);
      area += a.x() * b.y() - b.x() * a.y();
      for (const auto& q : curves[name].back())
        loop.push_back(q);
    }
    EXPECT_GT(area, 0) << "loops run counter-clockwise (y up)";
    const auto segs = expectedPiece(*w.first, w.second);
    const Polyline expect = sampleSegments(segs);
    RebuildBounds bl, be;
    for (const auto& q : loop)
      bl.add(q);
    for (const auto& q : expect)
      be.add(q);
    const Point2 shift = be.min - bl.min;
    std::vector<std::pair<Point2, Point2>> loopSegs;
    for (size_t i = 0; i + 1 < loop.size(); ++i)
      loopSegs.emplace_back(loop[i] + shift, loop[i + 1] + shift);
    double err = 0;
    for (const auto& q : loop)
      err = std::max(err, distToSegments(q + shift, segs));
    for (const auto& q : expect)
      err = std::max(err, distToSegments(q, loopSegs));
    EXPECT_LT(err, 0.1) << "GarmentCode loop vs drafted piece, cm";
    if (worst)
      *worst = std::max(*worst, err);
  }

  // Stitches: real edges; each edge stitched at most once; lengths agree; every seam and dart
  // of the draft is stitched on every piece.
  std::map<std::string, std::set<size_t>> stitched;
  for (const auto& st : spec["pattern"]["stitches"]) {
    ASSERT_EQ(st.size(), 3u);
    double len[2];
    for (int s = 0; s < 2; ++s) {
      const std::string panel = st[s]["panel"];
      const size_t edge = st[s]["edge"];
      ASSERT_TRUE(curves.count(panel)) << panel;
      ASSERT_LT(edge, curves[panel].size());
      EXPECT_TRUE(stitched[panel].insert(edge).second) << panel << " edge " << edge << " twice";
      len[s] = length(curves[panel][edge]);
    }
    // Sleeve caps are eased into their armholes (up to 8 % longer); everything else matches.
    EXPECT_NEAR(len[0], len[1], std::max(0.1, 0.08 * std::max(len[0], len[1]))) << st.dump();
  }
  for (const auto& [name, w] : want) {
    double got = 0;
    for (size_t e : stitched[name])
      got += length(curves[name][e]);
    EXPECT_NEAR(got, expectedStitchedCm(pat, *w.first), 0.2) << name << ": stitched length";
  }

  // Placement: skirts and trousers hang from the waist, below the bodice.
  double bodiceLow = 1e300, lowerTop = -1e300;
  for (const auto& [name, w] : want) {
    const json& gp = panels[name];
    double top = -1e300, low = 1e300;
    for (const auto& v : gp["vertices"]) {
      top = std::max(top, v[1].get<double>() + gp["translation"][1].get<double>());
      low = std::min(low, v[1].get<double>() + gp["translation"][1].get<double>());
    }
    if (name.rfind("skirt", 0) == 0 || name.rfind("pants", 0) == 0)
      lowerTop = std::max(lowerTop, top);
    if (name.rfind("bodice", 0) == 0)
      bodiceLow = std::min(bodiceLow, low);
  }
  if (lowerTop > -1e300) {
    EXPECT_GT(lowerTop, 80.0);
    EXPECT_LT(lowerTop, 125.0);
  }
  if (lowerTop > -1e300 && bodiceLow < 1e300) {
    // Both waist lines are shaped (the skirt rises 1.2 cm at the side): within 3 cm.
    EXPECT_NEAR(bodiceLow, lowerTop, 3.0) << "bodice waist on the skirt's";
  }
}

}  // namespace garmcap::drafts::rebuild
