#include "garmcap/calib/slicer.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace garmcap::calib {

namespace {

std::uint64_t edgeKey(int a, int b) {
  if (a > b)
    std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}

double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

}  // namespace

std::vector<SliceLoop> sliceMesh(const TriMesh& mesh, double height) {
  // Each crossing edge yields one point; each crossed face links two of them. Walking the links
  // gives the loops. A vertex on the plane counts as above so no face is cut in a degenerate way.
  struct Node {
    Eigen::Vector2d point;
    std::uint64_t next[2] = {0, 0};
    int links = 0;
    bool visited = false;
  };
  std::unordered_map<std::uint64_t, Node> nodes;
  auto above = [&](int i) { return mesh.vertices[static_cast<std::size_t>(i)].y() >= height; };
  auto pointOn = [&](int a, int b) {
    const Eigen::Vector3d& pa = mesh.vertices[static_cast<std::size_t>(a)];
    const Eigen::Vector3d& pb = mesh.vertices[static_cast<std::size_t>(b)];
    const double t = (height - pa.y()) / (pb.y() - pa.y());
    const Eigen::Vector3d p = pa + t * (pb - pa);
    return Eigen::Vector2d(p.x(), p.z());
  };
  for (const auto& f : mesh.faces) {
    const bool u[3] = {above(f[0]), above(f[1]), above(f[2])};
    if (u[0] == u[1] && u[1] == u[2])
      continue;
    std::uint64_t keys[2];
    int n = 0;
    for (int k = 0; k < 3 && n < 2; ++k) {
      const int a = f[k], b = f[(k + 1) % 3];
      if (u[k] == u[(k + 1) % 3])
        continue;
      const std::uint64_t key = edgeKey(a, b);
      auto [it, inserted] = nodes.try_emplace(key);
      if (inserted)
        it->second.point = u[k] ? pointOn(b, a) : pointOn(a, b);
      keys[n++] = key;
    }
    if (n != 2)
      continue;
    for (int k = 0; k < 2; ++k) {
      Node& node = nodes[keys[k]];
      if (node.links < 2)
        node.next[node.links] = keys[1 - k];
      ++node.links;
    }
  }
  std::vector<SliceLoop> loops;
  for (auto& [startKey, start] : nodes) {
    if (start.visited || start.links != 2)
      continue;
    SliceLoop loop;
    std::uint64_t prev = startKey, cur = startKey;
    bool closed = false;
    while (true) {
      Node& node = nodes[cur];
      if (node.visited) {
        closed = (cur == startKey);
        break;
      }
      node.visited = true;
      loop.push_back(node.point);
      if (node.links != 2)
        break;
      const std::uint64_t nxt =
          (node.next[0] != prev || cur == startKey) ? node.next[0] : node.next[1];
      prev = cur;
      cur = nxt;
    }
    if (closed && loop.size() >= 3)
      loops.push_back(std::move(loop));
  }
  return loops;
}

std::vector<Eigen::Vector2d> convexHull(const std::vector<SliceLoop>& loops) {
  std::vector<Eigen::Vector2d> pts;
  for (const auto& l : loops)
    pts.insert(pts.end(), l.begin(), l.end());
  std::sort(pts.begin(), pts.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  if (pts.size() < 3)
    return pts;
  // Andrew's monotone chain.
  std::vector<Eigen::Vector2d> hull(2 * pts.size());
  std::size_t k = 0;
  for (const auto& p : pts) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 0)
      --k;
    hull[k++] = p;
  }
  for (std::size_t i = pts.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0)
      --k;
    hull[k++] = pts[i];
  }
  hull.resize(k - 1);
  return hull;
}

double polygonPerimeter(const std::vector<Eigen::Vector2d>& polygon) {
  double sum = 0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    sum += (polygon[(i + 1) % polygon.size()] - polygon[i]).norm();
  }
  return sum;
}

double polygonArea(const std::vector<Eigen::Vector2d>& polygon) {
  double a = 0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const auto& p = polygon[i];
    const auto& q = polygon[(i + 1) % polygon.size()];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

bool pointInPolygon(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& p) {
  bool inside = false;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const auto& a = polygon[i];
    const auto& b = polygon[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

}  // namespace garmcap::calib
