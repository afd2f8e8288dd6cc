#include "garmcap/calib/form_view.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include "garmcap/calib/slicer.h"

namespace garmcap::calib {

namespace {

// Sections are sampled this often along the height and interpolated per image row: the form's
// outline changes slowly, and slicing the mesh once per row would cost seconds at 12 MP.
constexpr double kSectionStepCm = 0.25;

struct Projected {
  double minX = std::numeric_limits<double>::max();
  double maxX = std::numeric_limits<double>::lowest();
  double sumY = 0;
  int n = 0;
};

void addPoint(Projected& p, const FormPose& pose, double x, double y, double z) {
  const Eigen::Vector2d q = calib::projectPoint(pose, {x, y, z});
  p.minX = std::min(p.minX, q.x());
  p.maxX = std::max(p.maxX, q.x());
  p.sumY += q.y();
  ++p.n;
}

double lerpD(double a, double b, double t) {
  return a + (b - a) * t;
}

std::optional<RowSection> lerpSection(const std::optional<RowSection>& a,
                                      const std::optional<RowSection>& b, double t) {
  if (!a || !b)
    return std::nullopt;
  RowSection s;
  s.heightCm = lerpD(a->heightCm, b->heightCm, t);
  s.leftPx = lerpD(a->leftPx, b->leftPx, t);
  s.rightPx = lerpD(a->rightPx, b->rightPx, t);
  s.circCm = lerpD(a->circCm, b->circCm, t);
  return s;
}

}  // namespace

double ArmAxis::halfWidthAt(double tPx) const {
  if (halfWidthPx.empty())
    return 0;
  const double i = std::clamp(tPx / binPx, 0.0, static_cast<double>(halfWidthPx.size() - 1));
  const auto i0 = static_cast<std::size_t>(std::floor(i));
  const std::size_t i1 = std::min(i0 + 1, halfWidthPx.size() - 1);
  return lerpD(halfWidthPx[i0], halfWidthPx[i1], i - static_cast<double>(i0));
}

double ArmAxis::centreAt(double tPx) const {
  if (centreOffsetPx.empty())
    return 0;
  const double i = std::clamp(tPx / binPx, 0.0, static_cast<double>(centreOffsetPx.size() - 1));
  const auto i0 = static_cast<std::size_t>(std::floor(i));
  const std::size_t i1 = std::min(i0 + 1, centreOffsetPx.size() - 1);
  return lerpD(centreOffsetPx[i0], centreOffsetPx[i1], i - static_cast<double>(i0));
}

FormView::FormView(const FormModel& form, const FormPose& pose, cv::Size size)
    : form_(&form), pose_(pose), size_(size) {
  if (std::abs(pose.rollRad) > 1e-12) {
    throw std::invalid_argument(
        "FormView: the pose must have no roll (the renderer rolls the image)");
  }
  const auto& lm = form.landmarks();
  if (!lm.bust || !lm.waist || !lm.hip || !lm.armpit) {
    throw std::invalid_argument(
        "the form has no bust, waist, hip or armpit landmark: the simulator dresses full torsos "
        "with arms only");
  }
  bust_ = *lm.bust;
  waist_ = *lm.waist;
  hip_ = *lm.hip;
  armpit_ = *lm.armpit;
  crotch_ = lm.crotch;
  neckSide_ = lm.neckBase ? *lm.neckBase : (lm.shoulder ? *lm.shoulder : armpit_ + 10.0);

  coverage_ = calib::renderCoverage(form.mesh(), pose, size, 4);
  const Eigen::Vector2d lo = calib::projectPoint(pose, {form.axisXCm(), form.minYCm(), 0});
  const Eigen::Vector2d hi = calib::projectPoint(pose, {form.axisXCm(), form.maxYCm(), 0});
  // The legs, feet or stand may leave the frame at the bottom (a station frames the garment);
  // the head and everything down to the hip must be in it.
  const double hipRow = calib::projectPoint(pose, {form.axisXCm(), hip_, 0}).y();
  if (hi.y() < 0 || lo.y() < 0 || hipRow >= size.height) {
    throw std::invalid_argument("the form does not fit in the " + std::to_string(size.width) + "x" +
                                std::to_string(size.height) +
                                " image with this pose (its head and hips must be in view)");
  }
  axisXPx_ = calib::projectPoint(pose, {form.axisXCm(), hip_, form.axisZCm()}).x();
  rasteriseNormals();
  buildRowTables();
  findArms();
}

void FormView::rasteriseNormals() {
  const auto& mesh = form_->mesh();
  std::vector<Eigen::Vector3d> vn(mesh.vertices.size(), Eigen::Vector3d::Zero());
  for (const auto& f : mesh.faces) {
    const Eigen::Vector3d n = (mesh.vertices[static_cast<std::size_t>(f[1])] -
                               mesh.vertices[static_cast<std::size_t>(f[0])])
                                  .cross(mesh.vertices[static_cast<std::size_t>(f[2])] -
                                         mesh.vertices[static_cast<std::size_t>(f[0])]);
    for (int k = 0; k < 3; ++k)
      vn[static_cast<std::size_t>(f[k])] += n;  // area weighted
  }
  std::vector<Eigen::Vector2d> vp(mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    vp[i] = calib::projectPoint(pose_, mesh.vertices[i]);
    const double len = vn[i].norm();
    if (len > 0)
      vn[i] /= len;
  }
  normals_ = cv::Mat3f(size_, cv::Vec3f(0, 0, 1));
  cv::Mat1f depth(size_, -std::numeric_limits<float>::max());
  for (const auto& f : mesh.faces) {
    const auto a = static_cast<std::size_t>(f[0]), b = static_cast<std::size_t>(f[1]),
               c = static_cast<std::size_t>(f[2]);
    const Eigen::Vector2d &p0 = vp[a], &p1 = vp[b], &p2 = vp[c];
    const double area = (p1 - p0).x() * (p2 - p0).y() - (p1 - p0).y() * (p2 - p0).x();
    if (std::abs(area) < 1e-12)
      continue;
    const int x0 = std::max(0, static_cast<int>(std::ceil(std::min({p0.x(), p1.x(), p2.x()}))));
    const int x1 =
        std::min(size_.width - 1, static_cast<int>(std::floor(std::max({p0.x(), p1.x(), p2.x()}))));
    const int y0 = std::max(0, static_cast<int>(std::ceil(std::min({p0.y(), p1.y(), p2.y()}))));
    const int y1 = std::min(size_.height - 1,
                            static_cast<int>(std::floor(std::max({p0.y(), p1.y(), p2.y()}))));
    for (int y = y0; y <= y1; ++y) {
      float* dRow = depth.ptr<float>(y);
      cv::Vec3f* nRow = normals_.ptr<cv::Vec3f>(y);
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2d p(x, y);
        const double w0 = ((p1 - p).x() * (p2 - p).y() - (p1 - p).y() * (p2 - p).x()) / area;
        const double w1 = ((p2 - p).x() * (p0 - p).y() - (p2 - p).y() * (p0 - p).x()) / area;
        const double w2 = 1.0 - w0 - w1;
        if (w0 < -1e-9 || w1 < -1e-9 || w2 < -1e-9)
          continue;
        const double z =
            w0 * mesh.vertices[a].z() + w1 * mesh.vertices[b].z() + w2 * mesh.vertices[c].z();
        if (z <= dRow[x])
          continue;
        dRow[x] = static_cast<float>(z);
        Eigen::Vector3d n = w0 * vn[a] + w1 * vn[b] + w2 * vn[c];
        const double len = n.norm();
        if (len > 0)
          n /= len;
        nRow[x] = cv::Vec3f(static_cast<float>(n.x()), static_cast<float>(n.y()),
                            static_cast<float>(n.z()));
      }
    }
  }
  // Silhouette pixels the rasteriser missed (coverage from a pixel corner): face the camera.
  bottomRow_ = 0;
  topOutline_.assign(static_cast<std::size_t>(size_.width), -1);
  // The shoulder line, not the head: only rows at or below the side neck count.
  const int neckRow = static_cast<int>(std::floor(rowOfHeight(neckSide_)));
  for (int y = 0; y < size_.height; ++y) {
    const float* c = coverage_.ptr<float>(y);
    for (int x = 0; x < size_.width; ++x) {
      if (c[x] > 0.5f) {
        bottomRow_ = y;
        if (y >= neckRow && topOutline_[static_cast<std::size_t>(x)] < 0)
          topOutline_[static_cast<std::size_t>(x)] = y;
      }
    }
  }
}

// World-space sections of one form, sampled along the height: the convex hulls (x, z) of the
// torso and of each leg, with their perimeters. They do not depend on the pose, and slicing the
// mesh a few hundred times costs far more than a render, so the form keeps them
// (FormModel::viewSections) for every view of it.
struct FormViewSections {
  struct Sample {
    double h = 0;
    std::vector<Eigen::Vector2d> torsoHull;  // empty when no torso section is used here
    double torsoCirc = 0;
    std::array<std::vector<Eigen::Vector2d>, 2> legHull;
    std::array<double, 2> legCirc{0, 0};
  };
  std::vector<Sample> samples;
};

namespace {

using WorldSample = FormViewSections::Sample;

std::shared_ptr<const FormViewSections> worldSamples(const FormModel& form, double armpit,
                                                     std::optional<double> crotch) {
  auto sections = std::make_shared<FormViewSections>();
  std::vector<WorldSample>* out = &sections->samples;
  const double axisX = form.axisXCm();
  for (double h = form.minYCm() + 0.5 * kSectionStepCm; h < form.maxYCm(); h += kSectionStepCm) {
    WorldSample w;
    w.h = h;
    const bool aboveCrotch = !crotch || h > *crotch;
    if (aboveCrotch && h > armpit) {
      out->push_back(std::move(w));
      continue;
    }
    const calib::FormSection s = form.section(h);
    if (aboveCrotch && !s.torsoLoops.empty() && s.circumferenceCm > 0) {
      w.torsoHull = calib::convexHull(s.torsoLoops);
      w.torsoCirc = s.circumferenceCm;
    } else if (!aboveCrotch) {
      // Below the crotch the torso loops are the legs: split them by the body axis.
      for (int side = 0; side < 2; ++side) {
        std::vector<calib::SliceLoop> mine;
        for (const auto& loop : s.torsoLoops) {
          double cx = 0;
          for (const auto& q : loop)
            cx += q.x();
          cx /= static_cast<double>(std::max<std::size_t>(1, loop.size()));
          if ((side == 0) == (cx < axisX))
            mine.push_back(loop);
        }
        if (mine.empty())
          continue;
        const auto k = static_cast<std::size_t>(side);
        w.legHull[k] = calib::convexHull(mine);
        w.legCirc[k] = calib::polygonPerimeter(w.legHull[k]);
      }
    }
    out->push_back(std::move(w));
  }
  return sections;
}

std::optional<RowSection> projectHull(const FormPose& pose,
                                      const std::vector<Eigen::Vector2d>& hull, double h,
                                      double circ) {
  if (hull.empty())
    return std::nullopt;
  Projected p;
  for (const auto& q : hull)
    addPoint(p, pose, q.x(), h, q.y());
  return RowSection{h, p.minX, p.maxX, circ};
}

}  // namespace

void FormView::buildRowTables() {
  const auto sections = form_->viewSections([&] { return worldSamples(*form_, armpit_, crotch_); });
  std::vector<std::optional<RowSection>> torso, leg0, leg1;
  for (const auto& w : sections->samples) {
    sampleHeights_.push_back(w.h);
    sampleRows_.push_back(
        calib::projectPoint(pose_, {form_->axisXCm(), w.h, form_->axisZCm()}).y());
    torso.push_back(projectHull(pose_, w.torsoHull, w.h, w.torsoCirc));
    leg0.push_back(projectHull(pose_, w.legHull[0], w.h, w.legCirc[0]));
    leg1.push_back(projectHull(pose_, w.legHull[1], w.h, w.legCirc[1]));
  }
  // Resample per image row (rows decrease as height increases).
  torsoRows_.assign(static_cast<std::size_t>(size_.height), std::nullopt);
  legRows_[0].assign(static_cast<std::size_t>(size_.height), std::nullopt);
  legRows_[1].assign(static_cast<std::size_t>(size_.height), std::nullopt);
  for (std::size_t i = 0; i + 1 < sampleHeights_.size(); ++i) {
    const double rA = sampleRows_[i], rB = sampleRows_[i + 1];  // rA > rB
    for (int row = static_cast<int>(std::ceil(rB)); row <= static_cast<int>(std::floor(rA));
         ++row) {
      if (row < 0 || row >= size_.height)
        continue;
      const double t = rA == rB ? 0.0 : (rA - row) / (rA - rB);
      const auto r = static_cast<std::size_t>(row);
      torsoRows_[r] = lerpSection(torso[i], torso[i + 1], t);
      legRows_[0][r] = lerpSection(leg0[i], leg0[i + 1], t);
      legRows_[1][r] = lerpSection(leg1[i], leg1[i + 1], t);
    }
  }
  // Side neck half-width.
  const calib::FormSection neck = form_->section(neckSide_);
  neckHalfWidthPx_ = 0.5 * neck.widthCm * pose_.pxPerCm;
}

double FormView::rowOfHeight(double heightCm) const {
  return calib::projectPoint(pose_, {form_->axisXCm(), heightCm, form_->axisZCm()}).y();
}

double FormView::heightOfRow(double row) const {
  // sampleRows_ decreases with height; invert by interpolation (extrapolate at the ends).
  const std::size_t n = sampleRows_.size();
  if (n < 2)
    return 0;
  std::size_t i = 0;
  while (i + 2 < n && sampleRows_[i + 1] > row)
    ++i;
  const double t = (sampleRows_[i] - row) / (sampleRows_[i] - sampleRows_[i + 1]);
  return lerpD(sampleHeights_[i], sampleHeights_[i + 1], t);
}

std::optional<RowSection> FormView::torsoAtRow(int row) const {
  if (row < 0 || row >= size_.height)
    return std::nullopt;
  return torsoRows_[static_cast<std::size_t>(row)];
}

std::optional<RowSection> FormView::torsoAtHeight(double heightCm) const {
  const calib::FormSection s = form_->section(heightCm);
  if (s.torsoLoops.empty() || s.circumferenceCm <= 0)
    return std::nullopt;
  Projected p;
  for (const auto& loop : s.torsoLoops) {
    for (const auto& q : loop)
      addPoint(p, pose_, q.x(), heightCm, q.y());
  }
  return RowSection{heightCm, p.minX, p.maxX, s.circumferenceCm};
}

std::optional<RowSection> FormView::legAtRow(int row, int side) const {
  if (row < 0 || row >= size_.height || side < 0 || side > 1)
    return std::nullopt;
  return legRows_[static_cast<std::size_t>(side)][static_cast<std::size_t>(row)];
}

void FormView::findArms() {
  const int armpitRow = static_cast<int>(std::ceil(rowOfHeight(armpit_))) + 2;
  const double margin = 0.5 * pose_.pxPerCm;
  // A torso form's stand is no arm: below the torso the "torso" row is the pole's, and the
  // foot beside it read as two arms (sleeved references were laid along them).
  const int lastRow =
      form_->isTorsoForm()
          ? std::clamp(static_cast<int>(std::floor(rowOfHeight(form_->torsoBottomCm() + 2.0))), 0,
                       size_.height)
          : size_.height;
  for (int side = 0; side < 2; ++side) {
    // Arm pixels: covered, below the armpit, outside the torso (or the legs) on this side.
    std::vector<Eigen::Vector2d> pts;
    for (int y = std::max(0, armpitRow); y < lastRow; ++y) {
      double inner;
      if (auto t = torsoAtRow(y)) {
        inner = side == 0 ? t->leftPx - margin : t->rightPx + margin;
      } else if (auto l = legAtRow(y, side)) {
        inner = side == 0 ? l->leftPx - margin : l->rightPx + margin;
      } else {
        continue;
      }
      const float* c = coverage_.ptr<float>(y);
      if (side == 0) {
        for (int x = 0; x < std::min(size_.width, static_cast<int>(inner)); ++x) {
          if (c[x] > 0.5f)
            pts.emplace_back(x, y);
        }
      } else {
        for (int x = std::max(0, static_cast<int>(inner) + 1); x < size_.width; ++x) {
          if (c[x] > 0.5f)
            pts.emplace_back(x, y);
        }
      }
    }
    if (pts.size() < 50)
      continue;
    // The upper arm above the armpit: outside the torso's edges at the armpit, below the side
    // neck. Used for the arm's width near the shoulder, not for its axis.
    std::vector<Eigen::Vector2d> upper;
    std::optional<RowSection> atArmpit;
    for (int y = armpitRow; y < size_.height && !atArmpit; ++y)
      atArmpit = torsoAtRow(y);
    if (atArmpit) {
      const double inner = side == 0 ? atArmpit->leftPx - margin : atArmpit->rightPx + margin;
      for (int y = std::max(0, static_cast<int>(std::ceil(rowOfHeight(neckSide_)))); y < armpitRow;
           ++y) {
        const float* c = coverage_.ptr<float>(y);
        for (int x = 0; x < size_.width; ++x) {
          if (c[x] > 0.5f && (side == 0 ? x < inner : x > inner))
            upper.emplace_back(x, y);
        }
      }
    }
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& p : pts)
      mean += p;
    mean /= static_cast<double>(pts.size());
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const auto& p : pts)
      cov += (p - mean) * (p - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
    Eigen::Vector2d dir = es.eigenvectors().col(1);
    if (dir.y() < 0)
      dir = -dir;

    // Shoulder tip from the top outline between the side neck and the arm's top edge at the
    // armpit's height: the corner where the gentle shoulder line (~20 degrees) turns into the
    // steeper arm (~45 degrees in an A-pose), taken as the outline point farthest above the
    // chord between those two ends. A slope threshold is not used: at a few px per cm the
    // outline's steps make the shoulder's slope cross any threshold near the neck.
    const int step = side == 0 ? -1 : 1;
    const int xNeck = static_cast<int>(std::lround(axisXPx_ + step * neckHalfWidthPx_));
    std::optional<Eigen::Vector2d> tip;
    if (xNeck >= 0 && xNeck < size_.width && topOutline_[static_cast<std::size_t>(xNeck)] >= 0) {
      int xEnd = xNeck;
      for (int x = xNeck; x >= 0 && x < size_.width; x += step) {
        const int y = topOutline_[static_cast<std::size_t>(x)];
        if (y < 0)
          break;
        xEnd = x;
        if (y >= armpitRow)
          break;
      }
      const Eigen::Vector2d a(xNeck, topOutline_[static_cast<std::size_t>(xNeck)]);
      const Eigen::Vector2d b(xEnd, topOutline_[static_cast<std::size_t>(xEnd)]);
      const Eigen::Vector2d chord = b - a;
      if (chord.norm() > 2 * pose_.pxPerCm) {
        double best = 0;
        for (int x = xNeck; x != xEnd + step; x += step) {
          const Eigen::Vector2d p(x, topOutline_[static_cast<std::size_t>(x)]);
          const Eigen::Vector2d r = p - a;
          // Signed height above the chord (image y grows downward): a cross product.
          const double above = -step * (r.y() * chord.x() - r.x() * chord.y()) / chord.norm();
          if (above > best) {
            best = above;
            tip = p;
          }
        }
      }
    }
    if (!tip)
      continue;
    ArmAxis arm;
    arm.dir = dir;
    arm.shoulderTipPx = *tip;
    if (atArmpit)
      arm.underarmPx = Eigen::Vector2d(side == 0 ? atArmpit->leftPx : atArmpit->rightPx,
                                       rowOfHeight(atArmpit->heightCm));
    arm.originPx = mean + dir * (*tip - mean).dot(dir);
    arm.binPx = std::max(1.0, pose_.pxPerCm);
    double tMax = 0;
    for (const auto& p : pts)
      tMax = std::max(tMax, arm.t(p));
    const auto bins = static_cast<std::size_t>(tMax / arm.binPx) + 1;
    std::vector<double> dMin(bins, std::numeric_limits<double>::max()),
        dMax(bins, std::numeric_limits<double>::lowest());
    pts.insert(pts.end(), upper.begin(), upper.end());
    for (const auto& p : pts) {
      const double t = arm.t(p);
      if (t < 0)
        continue;
      const auto b = static_cast<std::size_t>(t / arm.binPx);
      dMin[b] = std::min(dMin[b], arm.d(p));
      dMax[b] = std::max(dMax[b], arm.d(p));
    }
    arm.halfWidthPx.assign(bins, -1);
    arm.centreOffsetPx.assign(bins, 0);
    for (std::size_t b = 0; b < bins; ++b) {
      if (dMax[b] >= dMin[b]) {
        arm.halfWidthPx[b] = 0.5 * (dMax[b] - dMin[b]) + 0.5;
        arm.centreOffsetPx[b] = 0.5 * (dMax[b] + dMin[b]);
      }
    }
    // Near the shoulder the arm merges with the torso: carry the first measured bin upward,
    // and fill gaps from the previous bin.
    std::size_t first = 0;
    while (first < bins && arm.halfWidthPx[first] < 0)
      ++first;
    if (first == bins)
      continue;
    for (std::size_t b = 0; b < bins; ++b) {
      if (b < first) {
        arm.halfWidthPx[b] = arm.halfWidthPx[first];
        arm.centreOffsetPx[b] = arm.centreOffsetPx[first];
      } else if (arm.halfWidthPx[b] < 0) {
        arm.halfWidthPx[b] = arm.halfWidthPx[b - 1];
        arm.centreOffsetPx[b] = arm.centreOffsetPx[b - 1];
      }
    }
    // Above the armpit the torso's edge clips the arm's inner side, so those bins read too
    // narrow and off-centre: give them the arm's section just below the armpit, where it
    // leaves the torso.
    if (arm.underarmPx) {
      const double tArmpit = arm.t(*arm.underarmPx);
      if (tArmpit > 0) {
        const auto bArmpit =
            std::min(bins - 1, static_cast<std::size_t>(std::ceil(tArmpit / arm.binPx)));
        for (std::size_t b = 0; b < bArmpit; ++b) {
          if (arm.halfWidthPx[b] < arm.halfWidthPx[bArmpit]) {
            arm.halfWidthPx[b] = arm.halfWidthPx[bArmpit];
            arm.centreOffsetPx[b] = arm.centreOffsetPx[bArmpit];
          }
        }
      }
    }
    // Wrist: the narrowest part of the forearm. A hand seen edge-on (palm to the body, as in an
    // A-pose) can be narrower than the wrist, so the search stays where the wrist is on an
    // adult (shoulder tip to wrist ~ 0.74 of shoulder tip to fingertip), on a 3-bin average.
    double best = std::numeric_limits<double>::max();
    const auto b0 =
        std::max<std::size_t>(1, static_cast<std::size_t>(0.62 * static_cast<double>(bins)));
    const auto b1 = std::min(bins - 1, static_cast<std::size_t>(0.82 * static_cast<double>(bins)));
    for (std::size_t b = b0; b < b1; ++b) {
      const double w = arm.halfWidthPx[b - 1] + arm.halfWidthPx[b] + arm.halfWidthPx[b + 1];
      if (w < best) {
        best = w;
        arm.tWristPx = (static_cast<double>(b) + 0.5) * arm.binPx;
      }
    }
    arms_[static_cast<std::size_t>(side)] = arm;
  }
}

}  // namespace garmcap::calib
