// GarmentCode (pygarment) specification writer.
#include "garmcap/drafts/export_garmentcode.h"

#include <Eigen/Dense>
#include <algorithm>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "export_util.h"

namespace garmcap::drafts {
namespace {

using detail::Box;

// ---------------------------------------------------------------------------------------------
// GarmentCode: cubic Bezier through the polyline between two breakpoints, least squares on
// the two inner control points with chord-length parameters. Returns the control points.
std::pair<Point2, Point2> fitCubic(const std::vector<Point2>& q) {
  const Point2 p0 = q.front();
  const Point2 p3 = q.back();
  std::vector<double> t(q.size(), 0.0);
  for (size_t k = 1; k < q.size(); ++k)
    t[k] = t[k - 1] + (q[k] - q[k - 1]).norm();
  for (auto& v : t)
    v /= t.back();
  Eigen::Matrix2d m = Eigen::Matrix2d::Zero();
  Eigen::Matrix<double, 2, 2> rhs = Eigen::Matrix2d::Zero();  // rows: C1, C2; cols: x, y
  for (size_t k = 0; k < q.size(); ++k) {
    double s = 1 - t[k];
    double a = 3 * s * s * t[k];
    double b = 3 * s * t[k] * t[k];
    Point2 r = q[k] - s * s * s * p0 - t[k] * t[k] * t[k] * p3;
    m(0, 0) += a * a;
    m(0, 1) += a * b;
    m(1, 1) += b * b;
    rhs.row(0) += a * r.transpose();
    rhs.row(1) += b * r.transpose();
  }
  m(1, 0) = m(0, 1);
  Eigen::Matrix2d c = m.ldlt().solve(rhs);
  return {c.row(0).transpose(), c.row(1).transpose()};
}

Eigen::Vector2d relative(const Point2& start, const Point2& end, const Point2& c) {
  Point2 d = end - start;
  Point2 perp(-d.y(), d.x());
  double l2 = d.squaredNorm();
  return {(c - start).dot(d) / l2, (c - start).dot(perp) / l2};
}

}  // namespace

std::string garmentCodeJson(const Pattern& pattern, const PieceText& text) {
  using nlohmann::json;
  detail::checkPattern<GarmentCodeExportError>(pattern);
  json panels = json::object();
  json order = json::array();
  // panel name -> (original vertex index -> GarmentCode vertex index, reversed?)
  std::map<std::string, std::pair<std::map<int, int>, bool>> maps;
  std::map<std::string, int> vertexCount;
  const bool lower = pattern.type == "skirt" || pattern.type == "pants";
  for (const auto& p : pattern.panels) {
    detail::checkPanel<GarmentCodeExportError>(p);
    const auto& o = p.outline;
    const int n = static_cast<int>(o.size());
    // Breakpoints: seam ends always; turn points only outside seams, so that every seam side
    // is exactly one GarmentCode edge (its stitches are edge-to-edge).
    std::set<int> seamEnds;
    std::vector<std::pair<int, int>> seamRanges;
    for (const auto& s : pattern.seams)
      for (const auto* e : {&s.a, &s.b})
        if (e->panel == p.name) {
          if (e->from < 0 || e->from >= n || e->to < 0 || e->to >= n || e->from == e->to)
            throw GarmentCodeExportError("seam '" + s.name + "': edge of panel '" + p.name +
                                         "' has bad vertex range " + std::to_string(e->from) +
                                         ".." + std::to_string(e->to));
          seamEnds.insert(e->from);
          seamEnds.insert(e->to);
          seamRanges.emplace_back(e->from, e->to);
        }
    auto insideSeam = [&](int v) {
      for (auto [f, t] : seamRanges) {
        int len = (t - f + n) % n, pos = (v - f + n) % n;
        if (pos > 0 && pos < len)
          return true;
      }
      return false;
    };
    std::set<int> breaks = seamEnds;
    for (int v : turnPointIndices(p, pattern))
      if (!insideSeam(v))
        breaks.insert(v);
    if (breaks.size() < 3) {  // a loop needs at least 3 vertices: add evenly spaced ones
      for (int k = 0; k < 3; ++k)
        breaks.insert(k * n / 3);
    }
    // y up; make the loop counter-clockwise in y-up coordinates.
    std::vector<Point2> up(o.size());
    for (size_t i = 0; i < o.size(); ++i)
      up[i] = Point2(o[i].x(), -o[i].y());
    double area = 0;
    for (int i = 0; i < n; ++i) {
      const auto& a = up[static_cast<size_t>(i)];
      const auto& b = up[static_cast<size_t>((i + 1) % n)];
      area += a.x() * b.y() - b.x() * a.y();
    }
    const bool reversed = area < 0;
    std::vector<int> loop(breaks.begin(), breaks.end());
    if (reversed)
      std::reverse(loop.begin(), loop.end());
    Box bb;
    for (const auto& q : up)
      bb.add(q);
    // Start at the lowest-left vertex.
    auto startIt = std::min_element(loop.begin(), loop.end(), [&](int a, int b) {
      const auto& pa = up[static_cast<size_t>(a)];
      const auto& pb = up[static_cast<size_t>(b)];
      return std::make_pair(pa.y(), pa.x()) < std::make_pair(pb.y(), pb.x());
    });
    std::rotate(loop.begin(), startIt, loop.end());
    std::map<int, int> idx;
    json verts = json::array();
    for (size_t k = 0; k < loop.size(); ++k) {
      idx[loop[k]] = static_cast<int>(k);
      const auto& q = up[static_cast<size_t>(loop[k])];
      verts.push_back({q.x() - bb.min.x(), q.y() - bb.max.y()});
    }
    json edges = json::array();
    const int m = static_cast<int>(loop.size());
    for (int k = 0; k < m; ++k) {
      int a = loop[static_cast<size_t>(k)], b = loop[static_cast<size_t>((k + 1) % m)];
      std::vector<Point2> pts;
      int step = reversed ? -1 : 1;
      for (int v = a;; v = (v + step + n) % n) {
        pts.push_back(up[static_cast<size_t>(v)]);
        if (v == b)
          break;
      }
      json e = {{"endpoints", {k, (k + 1) % m}}};
      bool straight = true;
      const Point2 d = pts.back() - pts.front();
      for (const auto& q : pts) {
        Point2 r = q - pts.front();
        if (d.norm() > 0 && std::abs(d.x() * r.y() - d.y() * r.x()) / d.norm() > 0.01)
          straight = false;
      }
      if (!straight && pts.size() > 2 && d.norm() > 0) {
        auto [c1, c2] = fitCubic(pts);
        auto r1 = relative(pts.front(), pts.back(), c1);
        auto r2 = relative(pts.front(), pts.back(), c2);
        e["curvature"] = {{"type", "cubic"}, {"params", {{r1.x(), r1.y()}, {r2.x(), r2.y()}}}};
      }
      edges.push_back(e);
    }
    const bool back = p.name.find("back") != std::string::npos;
    const double z = back ? -20.0 : 20.0;
    const double top = lower ? 105.0 : 150.0;
    json panel = {{"translation", {-bb.width() / 2, top, z}},
                  {"rotation", {0.0, back ? 180.0 : 0.0, 0.0}},
                  {"vertices", verts},
                  {"edges", edges}};
    panels[p.name] = panel;
    order.push_back(p.name);
    maps[p.name] = {idx, reversed};
    vertexCount[p.name] = m;
  }
  auto edgeIndex = [&](const drafts::EdgeRef& e, const std::string& seam) {
    auto it = maps.find(e.panel);
    if (it == maps.end())
      throw GarmentCodeExportError("seam '" + seam + "' names unknown panel '" + e.panel + "'");
    const auto& [idx, reversed] = it->second;
    int gf = idx.at(e.from), gt = idx.at(e.to);
    int m = vertexCount[e.panel];
    int start = reversed ? gt : gf, end = reversed ? gf : gt;
    if ((start + 1) % m != end)
      throw GarmentCodeExportError(
          "seam '" + seam + "': edge of panel '" + e.panel +
          "' crosses another seam's end; GarmentCode stitches are edge to edge");
    return start;
  };
  json stitches = json::array();
  for (const auto& s : pattern.seams)
    stitches.push_back({{{"panel", s.a.panel}, {"edge", edgeIndex(s.a, s.name)}},
                        {{"panel", s.b.panel}, {"edge", edgeIndex(s.b, s.name)}},
                        "right_wrong"});
  json spec = {{"pattern", {{"panels", panels}, {"stitches", stitches}, {"panel_order", order}}},
               {"parameters", json::object()},
               {"parameter_order", json::array()},
               {"properties",
                {{"curvature_coords", "relative"},
                 {"normalize_panel_translation", false},
                 {"normalized_edge_loops", true},
                 {"units_in_meter", 100}}},
               {"garmcap", {{"style", text.style}, {"size", text.size}, {"type", pattern.type}}}};
  return spec.dump(2) + "\n";
}

}  // namespace garmcap::drafts
