#include "garmcap/calib/projection.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace garmcap::calib {

std::optional<double> FormPose::distanceCm() const {
  if (!perspective)
    return std::nullopt;
  return perspective->fx / pxPerCm;
}

namespace {

Eigen::Vector2d projectUnrotated(const FormPose& pose, const Eigen::Vector3d& p) {
  if (!pose.perspective) {
    return pose.offsetPx + pose.pxPerCm * Eigen::Vector2d(p.x(), -p.y());
  }
  const Intrinsics& k = *pose.perspective;
  const double d = k.fx / pose.pxPerCm;
  const double xc = (k.cx - pose.offsetPx.x()) / pose.pxPerCm;
  const double yc = (pose.offsetPx.y() - k.cy) * d / k.fy;
  const double depth = std::max(d - p.z(), 1e-6);
  return {k.cx + k.fx * (p.x() - xc) / depth, k.cy - k.fy * (p.y() - yc) / depth};
}

Eigen::Vector2d rotateAbout(const Eigen::Vector2d& q, const Eigen::Vector2d& centre, double roll) {
  // Counter-clockwise on screen: image y points down, so the matrix is the transpose of the
  // usual one.
  const double c = std::cos(roll), s = std::sin(roll);
  const Eigen::Vector2d d = q - centre;
  return centre + Eigen::Vector2d(c * d.x() + s * d.y(), -s * d.x() + c * d.y());
}

// Sets the pixels whose centres lie inside triangle abc (half-open on the right and bottom, so
// that triangles sharing an edge neither overlap nor leave gaps).
void rasterTriangle(cv::Mat1b& mask, Eigen::Vector2d a, Eigen::Vector2d b, Eigen::Vector2d c) {
  if (a.y() > b.y())
    std::swap(a, b);
  if (a.y() > c.y())
    std::swap(a, c);
  if (b.y() > c.y())
    std::swap(b, c);
  const int y0 = std::max(0, static_cast<int>(std::ceil(a.y())));
  const int y1 = std::min(mask.rows - 1, static_cast<int>(std::ceil(c.y())) - 1);
  if (c.y() - a.y() <= 0)
    return;
  for (int y = y0; y <= y1; ++y) {
    const double yy = y;
    const double tLong = (yy - a.y()) / (c.y() - a.y());
    const double xLong = a.x() + tLong * (c.x() - a.x());
    double xShort;
    if (yy < b.y()) {
      if (b.y() - a.y() <= 0)
        continue;
      xShort = a.x() + (yy - a.y()) / (b.y() - a.y()) * (b.x() - a.x());
    } else {
      if (c.y() - b.y() <= 0)
        continue;
      xShort = b.x() + (yy - b.y()) / (c.y() - b.y()) * (c.x() - b.x());
    }
    const double xl = std::min(xLong, xShort), xr = std::max(xLong, xShort);
    const int i0 = std::max(0, static_cast<int>(std::ceil(xl)));
    const int i1 = std::min(mask.cols - 1, static_cast<int>(std::ceil(xr)) - 1);
    if (i1 >= i0)
      std::fill(mask.ptr(y) + i0, mask.ptr(y) + i1 + 1, std::uint8_t{255});
  }
}

std::vector<Eigen::Vector2d> projectAll(const TriMesh& mesh, const FormPose& pose) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(mesh.vertices.size());
  for (const auto& v : mesh.vertices)
    out.push_back(projectPoint(pose, v));
  return out;
}

}  // namespace

Eigen::Vector2d projectPoint(const FormPose& pose, const Eigen::Vector3d& worldCm) {
  return rotateAbout(projectUnrotated(pose, worldCm), pose.offsetPx, pose.rollRad);
}

cv::Mat1b renderSilhouette(const TriMesh& mesh, const FormPose& pose, cv::Size size,
                           int subpixelBits) {
  // subpixelBits is kept for API stability: the rasteriser works in double precision.
  (void)subpixelBits;
  cv::Mat1b mask(size, std::uint8_t{0});
  const auto pts = projectAll(mesh, pose);
  for (const auto& f : mesh.faces) {
    rasterTriangle(mask, pts[static_cast<std::size_t>(f[0])], pts[static_cast<std::size_t>(f[1])],
                   pts[static_cast<std::size_t>(f[2])]);
  }
  return mask;
}

cv::Mat1f renderCoverage(const TriMesh& mesh, const FormPose& pose, cv::Size size,
                         int supersample) {
  cv::Mat1f coverage(size, 0.0f);
  const int ss = std::clamp(supersample, 1, 16);
  auto pts = projectAll(mesh, pose);
  // Only the bounding box of the projection is rendered at the higher resolution.
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& p : pts)
    lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const int x0 = std::max(0, static_cast<int>(std::floor(lo.x())) - 1);
  const int y0 = std::max(0, static_cast<int>(std::floor(lo.y())) - 1);
  const int x1 = std::min(size.width, static_cast<int>(std::ceil(hi.x())) + 2);
  const int y1 = std::min(size.height, static_cast<int>(std::ceil(hi.y())) + 2);
  if (x1 <= x0 || y1 <= y0)
    return coverage;
  cv::Mat1b big((y1 - y0) * ss, (x1 - x0) * ss, std::uint8_t{0});
  // Sub-pixel (i, j) of pixel (X, Y) has its centre at X - 0.5 + (i + 0.5) / ss.
  for (auto& p : pts) {
    p = (p - Eigen::Vector2d(x0 - 0.5, y0 - 0.5)) * ss - Eigen::Vector2d(0.5, 0.5);
  }
  for (const auto& f : mesh.faces) {
    rasterTriangle(big, pts[static_cast<std::size_t>(f[0])], pts[static_cast<std::size_t>(f[1])],
                   pts[static_cast<std::size_t>(f[2])]);
  }
  cv::Mat small;
  cv::resize(big, small, cv::Size(x1 - x0, y1 - y0), 0, 0, cv::INTER_AREA);
  small.convertTo(coverage(cv::Rect(x0, y0, x1 - x0, y1 - y0)), CV_32F, 1.0 / 255.0);
  return coverage;
}

std::optional<SilhouetteEdges> silhouetteEdges(const FormModel& form, const FormPose& pose,
                                               double heightCm) {
  const FormSection s = form.section(heightCm);
  if (s.torsoLoops.empty())
    return std::nullopt;
  FormPose upright = pose;
  upright.rollRad = 0;
  Eigen::Vector3d left, right, front;
  double minU = 1e300, maxU = -1e300, bestFront = -1e300, bestFrontDx = 1e300;
  for (const auto& loop : s.torsoLoops) {
    for (const auto& q : loop) {
      const Eigen::Vector3d p(q.x(), heightCm, q.y());
      const double u = projectUnrotated(upright, p).x();
      if (u < minU)
        minU = u, left = p;
      if (u > maxU)
        maxU = u, right = p;
    }
  }
  // Centre front: the front-most point on the body axis (interpolated along the loop edges that
  // cross x = axis), else the front-most point overall.
  for (const auto& loop : s.torsoLoops) {
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const auto& a = loop[i];
      const auto& b = loop[(i + 1) % loop.size()];
      const double ax = form.axisXCm();
      if ((a.x() - ax) * (b.x() - ax) <= 0 && a.x() != b.x()) {
        const double t = (ax - a.x()) / (b.x() - a.x());
        const double z = a.y() + t * (b.y() - a.y());
        if (z > bestFront)
          bestFront = z, bestFrontDx = 0, front = {ax, heightCm, z};
      }
    }
  }
  if (bestFrontDx != 0) {
    for (const auto& loop : s.torsoLoops) {
      for (const auto& q : loop) {
        if (q.y() > bestFront)
          bestFront = q.y(), front = {q.x(), heightCm, q.y()};
      }
    }
  }
  return SilhouetteEdges{projectPoint(pose, left), projectPoint(pose, right),
                         projectPoint(pose, front)};
}

std::vector<std::pair<std::string, Eigen::Vector2d>> landmarkPoints(const FormModel& form,
                                                                    const FormPose& pose) {
  std::vector<std::pair<std::string, Eigen::Vector2d>> out;
  for (const auto& name : FormLandmarks::names()) {
    const auto y = form.landmarks().get(name);
    if (!y)
      continue;
    const auto e = silhouetteEdges(form, pose, *y);
    if (!e)
      continue;
    out.emplace_back(name + "_left", e->left);
    out.emplace_back(name + "_right", e->right);
    out.emplace_back(name + "_centre", e->centreFront);
  }
  return out;
}

}  // namespace garmcap::calib
