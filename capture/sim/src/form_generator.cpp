#include "garmcap/sim/form_generator.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "garmcap/calib/slicer.h"

namespace garmcap::sim {

using calib::FormSidecar;
using calib::polygonPerimeter;
using calib::TriMesh;

double ellipsePerimeter(double a, double b) {
  const double h = (a - b) * (a - b) / ((a + b) * (a + b));
  return std::numbers::pi * (a + b) * (1 + 3 * h / (10 + std::sqrt(4 - 3 * h)));
}

namespace {

// Monotone cubic Hermite interpolation (Fritsch-Carlson): no overshoot, and a station that is a
// local extremum of the data gets slope 0, so it stays the extremum of the curve.
double pchip(const std::vector<double>& x, const std::vector<double>& y, double t) {
  const std::size_t n = x.size();
  if (t <= x.front())
    return y.front();
  if (t >= x.back())
    return y.back();
  std::size_t k = static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), t) - x.begin()) - 1;
  auto secant = [&](std::size_t i) { return (y[i + 1] - y[i]) / (x[i + 1] - x[i]); };
  auto slope = [&](std::size_t i) {
    if (i == 0)
      return secant(0);
    if (i == n - 1)
      return secant(n - 2);
    const double d0 = secant(i - 1), d1 = secant(i);
    if (d0 * d1 <= 0)
      return 0.0;
    const double h0 = x[i] - x[i - 1], h1 = x[i + 1] - x[i];
    const double w1 = 2 * h1 + h0, w2 = h1 + 2 * h0;
    return (w1 + w2) / (w1 / d0 + w2 / d1);
  };
  const double h = x[k + 1] - x[k];
  const double s = (t - x[k]) / h;
  const double h00 = (1 + 2 * s) * (1 - s) * (1 - s), h10 = s * (1 - s) * (1 - s);
  const double h01 = s * s * (3 - 2 * s), h11 = s * s * (s - 1);
  return h00 * y[k] + h10 * h * slope(k) + h01 * y[k + 1] + h11 * h * slope(k + 1);
}

double need(const drafts::Measurements& m, const std::string& name) {
  const auto& v = m.values();
  auto it = v.find(name);
  if (it == v.end()) {
    throw std::invalid_argument("parametric form: measurement '" + name + "' is required");
  }
  if (!(it->second > 0)) {
    throw std::invalid_argument("parametric form: measurement '" + name + "' must be positive");
  }
  return it->second;
}

double optional(const drafts::Measurements& m, const std::string& name, double fallback) {
  const auto& v = m.values();
  auto it = v.find(name);
  return it == v.end() ? fallback : it->second;
}

// A closed polygon ring in 3D (all rings of one tube have the same vertex count).
using Ring = std::vector<Eigen::Vector3d>;

// Tube through `rings` closed by a fan to `startCap` and `endCap`.
TriMesh tube(const std::vector<Ring>& rings, const Eigen::Vector3d& startCap,
             const Eigen::Vector3d& endCap) {
  TriMesh m;
  const int n = static_cast<int>(rings.front().size());
  for (const auto& r : rings)
    m.vertices.insert(m.vertices.end(), r.begin(), r.end());
  const int capA = static_cast<int>(m.vertices.size());
  m.vertices.push_back(startCap);
  const int capB = capA + 1;
  m.vertices.push_back(endCap);
  for (int k = 0; k + 1 < static_cast<int>(rings.size()); ++k) {
    for (int i = 0; i < n; ++i) {
      const int a = k * n + i, b = k * n + (i + 1) % n;
      const int c = (k + 1) * n + (i + 1) % n, d = (k + 1) * n + i;
      m.faces.emplace_back(a, c, b);
      m.faces.emplace_back(a, d, c);
    }
  }
  const int last = (static_cast<int>(rings.size()) - 1) * n;
  for (int i = 0; i < n; ++i) {
    m.faces.emplace_back(capA, i, (i + 1) % n);
    m.faces.emplace_back(capB, last + (i + 1) % n, last + i);
  }
  return m;
}

// Ring of an ellipse with semi-axes a (along u) and b (along v) around `centre`, scaled so that
// its perimeter is exactly `perimeter`.
Ring ellipseRing(const Eigen::Vector3d& centre, const Eigen::Vector3d& u, const Eigen::Vector3d& v,
                 double a, double b, int n, double perimeter) {
  std::vector<Eigen::Vector2d> flat;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * std::numbers::pi * i / n;
    flat.emplace_back(a * std::cos(t), b * std::sin(t));
  }
  const double s = perimeter / polygonPerimeter(flat);
  Ring r;
  for (const auto& p : flat)
    r.push_back(centre + s * (p.x() * u + p.y() * v));
  return r;
}

}  // namespace

ParametricForm::ParametricForm(const drafts::Measurements& body, FormKind kind)
    : body_(body), kind_(kind) {
  const double H = need(body, "height");
  const double bust = need(body, "bust_circ");
  const double waist = need(body, "waist_circ");
  const double hip = need(body, "hip_circ");
  if (H < 100 || H > 220) {
    throw std::invalid_argument("parametric form: height must be 100..220 cm");
  }
  if (waist >= bust || waist >= hip) {
    throw std::invalid_argument(
        "parametric form: waist_circ must be smaller than bust_circ and hip_circ");
  }
  const double neck = optional(body, "neck_circ", 0.42 * bust);
  const double wrist = optional(body, "arm_wrist_circ", 0.18 * bust);
  const double backLength = optional(body, "neck_back_to_waist_b", 0.228 * H);
  const double waistToHip = optional(body, "waist_to_hip_b", 0.11 * H);
  double crotch = optional(body, "leg_crotch_to_floor", 0.455 * H);
  const double shoulders = optional(body, "shoulder_tip_to_shoulder_tip_b", 0.225 * H);
  const double sleeve = optional(body, "arm_shoulder_tip_to_wrist", 0.333 * H);
  const double bpbp = optional(body, "bustpoint_to_bustpoint", 0.2 * bust);
  const double neckToBp = optional(body, "bustpoint_to_neck_side", 0.14 * H);

  height_ = H;
  const double yWaist =
      optional(body, "height_waist_side", optional(body, "leg_waist_side_to_floor", 0.615 * H));
  const double yHip = yWaist - waistToHip;
  if (!body.has("leg_crotch_to_floor") && body.has("rise_length_side")) {
    crotch = yWaist - body.values().at("rise_length_side");
  }
  const double yNeck = yWaist + backLength;
  const double neckR = neck / (2 * std::numbers::pi);
  const double dx = std::max(0.0, bpbp / 2 - neckR);
  const double yBust = yNeck - std::sqrt(std::max(0.0, neckToBp * neckToBp - dx * dx));
  const double yShoulder = yNeck - 0.035 * H;
  const double yArmpit = yShoulder - 0.075 * H;
  const double yUnderbust = yBust - 0.05 * H;
  const double yChin = std::max(yNeck + 4, 0.87 * H);
  crotchY_ = crotch;
  topY_ = H;
  std::ostringstream order;
  if (!(crotch + 3 < yHip && yHip + 5 < yWaist && yWaist + 4 < yUnderbust && yBust + 2 < yArmpit &&
        yNeck + 3 < yChin && yChin + 12 < H)) {
    order << "parametric form: landmarks out of order (crotch " << crotch << ", hip " << yHip
          << ", waist " << yWaist << ", bust " << yBust << ", armpit " << yArmpit << ", neck "
          << yNeck << " cm): check leg_crotch_to_floor, waist_to_hip_b, neck_back_to_waist_b and "
          << "bustpoint_to_neck_side";
    throw std::invalid_argument(order.str());
  }
  shoulderHalfWidth_ = shoulders / 2;
  upperArmR_ = 0.31 * bust / (2 * std::numbers::pi);
  wristR_ = wrist / (2 * std::numbers::pi);
  armLength_ = sleeve;
  thighR_ = 0.075 * hip;
  legGap_ = 1.0;
  armAngleRad_ = 40.0 * std::numbers::pi / 180.0;

  // Shoulder ring: as wide as the shoulders less the arm's flesh, flat front to back.
  const double shoulderA = shoulderHalfWidth_ - 1.0;
  const double shoulderR = 0.42;
  const double headC = 0.33 * H;
  const double yHead = (yChin + H) / 2 + 1;
  stY_ = {crotch,    yHip,  yWaist, yUnderbust, yBust,   yArmpit,
          yShoulder, yNeck, yChin,  yHead,      H - 1.5, H};
  stC_ = {0.93 * hip,
          hip,
          waist,
          waist + 0.45 * (bust - waist),
          bust,
          0.97 * bust,
          ellipsePerimeter(shoulderA, shoulderR * shoulderA),
          neck,
          0.95 * neck,
          headC,
          0.5 * headC,
          0.0};
  stR_ = {0.72, 0.72, 0.74, 0.74, 0.78, 0.70, shoulderR, 0.85, 0.9, 1.2, 1.1, 1.0};
  heights_ = {{"crotch", crotch},  {"hip", yHip},           {"waist", yWaist},   {"bust", yBust},
              {"armpit", yArmpit}, {"shoulder", yShoulder}, {"neck_base", yNeck}};
  if (kind_ == FormKind::kTorso) {
    // A neck cap instead of chin and head: the neck goes on straight for a short way and ends
    // flat. The last two stations stand for the two the mesh loop leaves out (see mesh()).
    const double yCap = yNeck + 0.025 * H;
    stY_ = {crotch,    yHip,  yWaist, yUnderbust, yBust,   yArmpit,
            yShoulder, yNeck, yCap,   yCap + 1,   yCap + 2};
    stC_ = {stC_[0], stC_[1], stC_[2], stC_[3], stC_[4], stC_[5], stC_[6], neck, neck, neck, neck};
    stR_ = {0.72, 0.72, 0.74, 0.74, 0.78, 0.70, shoulderR, 0.85, 0.85, 0.85, 0.85};
    topY_ = yCap;
    height_ = yCap;
    heights_["top"] = yCap;
  }
}

double ParametricForm::girthAt(double y) const {
  return pchip(stY_, stC_, y);
}
double ParametricForm::ratioAt(double y) const {
  return pchip(stY_, stR_, y);
}

double ParametricForm::exactCircumferenceCm(double y) const {
  if (y < crotchY_ || y >= topY_)
    return 0;
  return girthAt(y);
}

TriMesh ParametricForm::mesh(double ringStepCm, int segments) const {
  const Eigen::Vector3d ex(1, 0, 0), ey(0, 1, 0), ez(0, 0, 1);
  TriMesh out;

  // Torso: uniform ring heights plus the girth stations themselves, so that slicing at a
  // station returns the station's girth exactly.
  std::vector<double> ys;
  for (double y = crotchY_; y < topY_ - 0.5 * ringStepCm; y += ringStepCm)
    ys.push_back(y);
  for (std::size_t i = 0; i + 2 < stY_.size(); ++i)
    ys.push_back(stY_[i]);
  std::sort(ys.begin(), ys.end());
  std::vector<double> kept;
  for (double y : ys) {
    if (kept.empty() || y - kept.back() > 0.2 * ringStepCm) {
      kept.push_back(y);
    } else if (std::find(stY_.begin(), stY_.end(), y) != stY_.end()) {
      kept.back() = y;  // a station wins over a nearby grid height
    }
  }
  std::vector<Ring> rings;
  for (double y : kept) {
    const double c = girthAt(y), r = ratioAt(y);
    const double a = c / ellipsePerimeter(1.0, r);
    rings.push_back(ellipseRing({0, y, 0}, ex, ez, a, r * a, segments, c));
  }
  // (A torso form's last ring is its neck cap's station: the cap is flat.)
  out.append(tube(rings, {0, crotchY_, 0}, {0, topY_, 0}));

  if (kind_ == FormKind::kTorso) {
    // The stand: a pole from the foot up into the torso (overlapping it by 2 cm, as the limbs
    // do) and a flat round foot on the floor.
    const int poleSegments = std::max(12, segments / 4);
    const double r = kTorsoPoleRadiusCm, fr = kTorsoFootRadiusCm, fh = kTorsoFootHeightCm;
    std::vector<Ring> pole;
    for (double y : {fh - 0.5, crotchY_ + 2.0})
      pole.push_back(ellipseRing({0, y, 0}, ex, ez, r, r, poleSegments, 2 * std::numbers::pi * r));
    out.append(tube(pole, {0, fh - 0.5, 0}, {0, crotchY_ + 2.0, 0}));
    std::vector<Ring> foot;
    for (double y : {0.0, fh})
      foot.push_back(ellipseRing({0, y, 0}, ex, ez, fr, fr, segments, 2 * std::numbers::pi * fr));
    out.append(tube(foot, {0, 0, 0}, {0, fh, 0}));
    return out;
  }

  // Legs: horizontal circular rings from just inside the torso down to the floor.
  const int limbSegments = std::max(12, segments / 2);
  const double legStep = 1.5 * ringStepCm;
  const double H = height_;
  const std::vector<double> legY = {0.0, 0.05 * H, 0.2 * H, 0.27 * H, crotchY_, crotchY_ + 2.0};
  const std::vector<double> legR = {0.55, 0.5, 0.78, 0.72, 1.0, 1.0};
  for (int side : {-1, 1}) {
    const double xTop = side * (thighR_ + legGap_ / 2);
    std::vector<Ring> legRings;
    std::vector<double> yl;
    for (double y = crotchY_ + 2.0; y > 0; y -= legStep)
      yl.push_back(y);
    yl.push_back(0.0);
    for (double y : yl) {
      const double rad = thighR_ * pchip(legY, legR, y);
      // Legs stay vertical; their centre moves in slightly towards the ankles.
      const double x = xTop * (0.9 + 0.1 * y / (crotchY_ + 2.0));
      legRings.push_back(
          ellipseRing({x, y, 0}, ex, ez, rad, rad, limbSegments, 2 * std::numbers::pi * rad));
    }
    const double xBottom = xTop * 0.9;
    out.append(tube(legRings, {xTop, crotchY_ + 2.0, 0}, {xBottom, 0, 0}));
  }

  // Arms: tubes from the shoulder joint down and out at the A-pose angle; rings perpendicular to
  // the arm axis; the hand is a rounded end.
  const double yShoulder = heights_.at("shoulder");
  const double handLength = 0.1 * H;
  const double armStep = 1.5 * ringStepCm;
  for (int side : {-1, 1}) {
    const Eigen::Vector3d joint(side * (shoulderHalfWidth_ - upperArmR_), yShoulder - upperArmR_,
                                0);
    const Eigen::Vector3d dir(side * std::sin(armAngleRad_), -std::cos(armAngleRad_), 0);
    const Eigen::Vector3d u(side * std::cos(armAngleRad_), std::sin(armAngleRad_), 0);
    const std::vector<double> sS = {0.0, 0.55 * armLength_, armLength_};
    const std::vector<double> sR = {upperArmR_, 0.85 * upperArmR_, wristR_};
    std::vector<Ring> armRings;
    const double total = armLength_ + handLength;
    for (double s = 0; s < total - 0.5 * armStep; s += armStep) {
      double rad;
      if (s <= armLength_) {
        rad = pchip(sS, sR, s);
      } else {
        const double t = (s - armLength_) / handLength;
        rad = wristR_ * 1.1 * std::sqrt(std::max(0.0, 1 - t * t)) + 0.02 * wristR_;
      }
      armRings.push_back(
          ellipseRing(joint + s * dir, u, ez, rad, rad, limbSegments, 2 * std::numbers::pi * rad));
    }
    out.append(tube(armRings, joint, joint + total * dir));
  }
  return out;
}

FormSidecar ParametricForm::sidecar(const std::string& meshFileName) const {
  FormSidecar s;
  s.mesh = meshFileName;
  s.meshUnits = "cm";
  s.name = "parametric form";
  s.orientation = "y up, floor at y = 0, facing +z, arms in an A-pose 40 degrees from vertical";
  for (const char* name : {"height", "bust_circ", "waist_circ", "hip_circ"}) {
    // A torso form has no stature: its top is a neck cap, and its height is the stand's.
    if (kind_ == FormKind::kTorso && std::string_view(name) == "height")
      continue;
    s.measurements.set(name, body_.values().at(name));
  }
  if (kind_ == FormKind::kTorso) {
    s.name = "parametric torso form";
    s.orientation =
        "y up, floor at y = 0, facing +z; torso dress form (neck cap, no head, arms or legs) on a "
        "pole";
    s.measurements.set("neck_circ", stC_[7]);
    for (const char* name : {"bust", "waist", "hip"})
      s.landmarkHeightsCm[name] = heights_.at(name);
    s.source =
        "garmcap parametric form generator, torso variant (capture/sim/src/form_generator.cpp)";
    return s;
  }
  s.measurements.set("neck_circ", stC_[7]);
  s.measurements.set("arm_wrist_circ", 2 * std::numbers::pi * wristR_);
  for (const char* name : {"bust", "waist", "hip", "crotch"}) {
    s.landmarkHeightsCm[name] = heights_.at(name);
  }
  s.source = "garmcap parametric form generator (calib/src/form_generator.cpp)";
  return s;
}

}  // namespace garmcap::sim
