#include "garmcap/calib/registration.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <set>
#include <sstream>

#include "garmcap/calib/errors.h"
#include "garmcap/drafts/file_io.h"

namespace garmcap::calib {

namespace {

struct Shape {
  double area;
  Eigen::Vector2d centroid;
  double angle;  // principal axis angle, radians (image coordinates)
  // How well the principal axis is defined: |mu20 - mu02| / (mu20 + mu02), 0 for a shape as wide
  // as it is tall (a form cut near its hips, arms out), where the axis turns by 90 degrees.
  double anisotropy;
};

constexpr double kMinAnisotropy = 0.15;

Shape shapeOf(const cv::Mat1f& coverage) {
  const cv::Moments m = cv::moments(coverage, false);
  Shape s;
  s.area = m.m00;
  s.centroid = {m.m10 / m.m00, m.m01 / m.m00};
  s.angle = 0.5 * std::atan2(2 * m.mu11, m.mu20 - m.mu02);
  s.anisotropy = m.mu20 + m.mu02 > 0 ? std::abs(m.mu20 - m.mu02) / (m.mu20 + m.mu02) : 0;
  return s;
}

double iouOf(const cv::Mat1b& a, const cv::Mat1b& b) {
  const double inter = cv::countNonZero(a & b);
  const double uni = cv::countNonZero(a | b);
  return uni > 0 ? inter / uni : 0;
}

Eigen::Vector2d rotate(const Eigen::Vector2d& d, double roll) {
  // Same convention as projection.cpp: counter-clockwise on screen (image y down).
  const double c = std::cos(roll), s = std::sin(roll);
  return {c * d.x() + s * d.y(), -s * d.x() + c * d.y()};
}

// The form height on its axis (plane z = 0) seen at image row `row`: the projection is monotone
// in height along the axis for the small rolls a station has, so bisection finds it.
double heightAtRow(const FormModel& form, const FormPose& pose, double row) {
  double lo = form.minYCm() - form.heightCm(), hi = form.maxYCm() + form.heightCm();
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    // Image rows grow downward: a point below the row is lower on the form.
    if (projectPoint(pose, {form.axisXCm(), mid, 0}).y() > row)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

// How much of a torso form's pole is kept in the fit, below the torso's bottom (cm).
constexpr double kStandKeptCm = 3.0;

// A copy of `m` with every row from `row` down cleared.
template <class M>
M clearedBelow(const M& m, double row) {
  M out = m.clone();
  const int r = std::clamp(static_cast<int>(std::ceil(row)), 0, out.rows);
  if (r < out.rows)
    out.rowRange(r, out.rows).setTo(0);
  return out;
}

}  // namespace

Registration registerForm(const FormModel& form, const cv::Mat3b& frame, const std::string& what,
                          const RegistrationOptions& opt) {
  const KeyResult key = keyGreenScreen(frame, what, opt.key);
  Shape obs = shapeOf(key.alpha);
  // A torso form's stand (pole and foot) is fitted on the torso and the top of its pole only: a
  // shop's stand is rarely the one in the mesh (height, tripod or disc), and its foot stands in
  // the floor's shadow, which keys as form (a simulated hard case's foot moved the fit by 22 px,
  // scale by 1.1 %). Both silhouettes are cleared below the row, under the current pose, of
  // kStandKeptCm below the torso's bottom.
  const bool onStand = form.isTorsoForm();
  auto standRow = [&](const FormPose& p) {
    return projectPoint(p, {form.axisXCm(), form.torsoBottomCm() - kStandKeptCm, form.axisZCm()})
        .y();
  };
  const cv::Size size = frame.size();

  // Start: the model's projected height matched to the observed silhouette's height.
  Registration reg;
  reg.imageSize = size;
  reg.screenBgr = key.screenBgr;
  FormPose& pose = reg.pose;
  if (opt.intrinsics && opt.distanceCm)
    pose.perspective = *opt.intrinsics;
  const cv::Rect box = cv::boundingRect(key.mask);
  // A form cut off at the bottom starts from the same guess (too small a scale); the model is
  // rendered into the frame and clipped at its bottom edge like the form, so the moments'
  // fixed point is still the pose that reproduces the visible part. It converges more slowly.
  pose.pxPerCm = box.height / form.heightCm();
  const int maxIterations = key.cutAtBottom ? 4 * opt.maxIterations : opt.maxIterations;
  if (pose.perspective) {
    // Distance sets the scale in perspective; start from the given distance only when it agrees
    // roughly with the observed height, else from the height.
    const double fromDistance = pose.perspective->fx / *opt.distanceCm;
    if (std::abs(fromDistance / pose.pxPerCm - 1) < 0.3 ||
        (key.cutAtBottom && fromDistance > pose.pxPerCm && fromDistance < 4 * pose.pxPerCm))
      pose.pxPerCm = fromDistance;
  }
  // The start's vertical place: the feet on the silhouette's lowest row, or, when the frame
  // cuts the form, the head on its top row.
  pose.offsetPx = {box.x + box.width / 2.0,
                   key.cutAtBottom ? box.y + form.maxYCm() * pose.pxPerCm
                                   : box.y + box.height + form.minYCm() * pose.pxPerCm};

  // Moment matching: scale from the area ratio, offset from the centroids, roll from the
  // principal axes; a similarity about the observed centroid, iterated on the rendered model.
  double prevScale = 0, prevArea = 0;
  for (reg.iterations = 1; reg.iterations <= maxIterations; ++reg.iterations) {
    cv::Mat1f model = renderCoverage(form.mesh(), pose, size, opt.supersample);
    if (onStand) {
      const double row = standRow(pose);
      model = clearedBelow(model, row);
      obs = shapeOf(clearedBelow(key.alpha, row));
    }
    const Shape mod = shapeOf(model);
    if (mod.area <= 0)
      break;
    // The visible area grows as the scale squared when the whole form is in view. When the frame
    // cuts the form, a larger scale also pushes more of it out of view and the area grows more
    // slowly: its growth exponent is then read off the last two iterations (secant), or the
    // square-root step undershoots and a form cut near its hip took more iterations than allowed.
    double exponent = 2.0;
    if (key.cutAtBottom && prevScale > 0 && std::abs(std::log(pose.pxPerCm / prevScale)) > 1e-6)
      exponent =
          std::clamp(std::log(mod.area / prevArea) / std::log(pose.pxPerCm / prevScale), 0.5, 2.0);
    prevScale = pose.pxPerCm;
    prevArea = mod.area;
    const double k = std::pow(obs.area / mod.area, 1.0 / exponent);
    double dRoll = -(obs.angle - mod.angle);  // image angle is clockwise-positive on screen
    while (dRoll > std::numbers::pi / 2)
      dRoll -= std::numbers::pi;
    while (dRoll < -std::numbers::pi / 2)
      dRoll += std::numbers::pi;
    // A principal axis that is barely defined gives no roll (the roll stays at its start, 0):
    // cut at the bottom, a form with its arms out can be about as wide as the part in view is
    // tall, and the axes' angle then swings by up to 90 degrees between iterations.
    if (std::min(obs.anisotropy, mod.anisotropy) < kMinAnisotropy)
      dRoll = 0;
    pose.offsetPx = obs.centroid + k * rotate(pose.offsetPx - mod.centroid, dRoll);
    pose.pxPerCm *= k;
    pose.rollRad += dRoll;
    const double shift = (obs.centroid - mod.centroid).norm();
    if (std::abs(k - 1) < 2e-5 && shift < 0.01 && std::abs(dRoll) < 1e-5)
      break;
  }
  reg.iterations = std::min(reg.iterations, maxIterations);
  reg.modelMask = renderSilhouette(form.mesh(), pose, size);
  reg.observedMask = key.mask;
  reg.iou = onStand ? iouOf(clearedBelow(reg.modelMask, standRow(pose)),
                            clearedBelow(reg.observedMask, standRow(pose)))
                    : iouOf(reg.modelMask, reg.observedMask);
  if (key.cutAtBottom) {
    reg.frameBottomCm = heightAtRow(form, pose, size.height);
    const auto& lm = form.landmarks();
    const std::optional<double> needed = lm.hip ? lm.hip : lm.waist;
    const char* neededName = lm.hip ? "hip" : "waist";
    if (!needed || *reg.frameBottomCm > *needed - kMinBelowHipCm) {
      std::ostringstream msg;
      msg.precision(1);
      msg << std::fixed << what << ": the form is cut off by the frame's bottom edge at "
          << *reg.frameBottomCm << " cm on the form";
      if (needed)
        msg << ", less than " << kMinBelowHipCm << " cm below its " << neededName << " (" << *needed
            << " cm)";
      msg << "; registration needs the form from its head to below its hips in view: move the "
             "camera back, lower it or zoom out";
      throw CalibError(CalibErrorKind::kFormCutOff, msg.str());
    }
  }
  if (reg.iou < opt.minIou) {
    std::ostringstream msg;
    msg << what << ": the form model does not match the silhouette in the frame (IoU " << reg.iou
        << " < " << opt.minIou << "): is it the right form, bare, and facing the "
        << "camera?";
    if (key.cutAtBottom) {
      // Too little of the form in view fits many poses badly: the fit then drifts, and the
      // frame's edge is the likelier cause than the form.
      msg << " The form also runs out of the frame at the bottom: registration needs it from "
             "its head to at least "
          << kMinBelowHipCm << " cm below its hip in view; move the camera back, lower it or "
          << "zoom out";
      throw CalibError(CalibErrorKind::kFormCutOff, msg.str());
    }
    throw CalibError(CalibErrorKind::kFitFailed, msg.str());
  }
  reg.landmarks = landmarkPoints(form, pose);
  return reg;
}

cv::Mat3b drawOverlay(const cv::Mat3b& frame, const Registration& reg) {
  cv::Mat3b out = frame.clone();
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(reg.observedMask.clone(), contours, cv::RETR_LIST, cv::CHAIN_APPROX_NONE);
  cv::drawContours(out, contours, -1, cv::Scalar(0, 255, 0), 1);
  contours.clear();
  cv::findContours(reg.modelMask.clone(), contours, cv::RETR_LIST, cv::CHAIN_APPROX_NONE);
  cv::drawContours(out, contours, -1, cv::Scalar(255, 0, 255), 1);
  const int r = std::max(2, out.rows / 300);
  const double fontScale = std::max(0.35, out.rows / 2000.0);
  for (const auto& [name, p] : reg.landmarks) {
    const cv::Point c(static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y())));
    cv::circle(out, c, r, cv::Scalar(0, 0, 255), cv::FILLED);
    if (name.ends_with("_right")) {
      cv::putText(out, name.substr(0, name.size() - 6), c + cv::Point(2 * r, 0),
                  cv::FONT_HERSHEY_SIMPLEX, fontScale, cv::Scalar(0, 0, 255), 1);
    }
  }
  std::ostringstream text;
  text.precision(4);
  text << "px/cm " << reg.pose.pxPerCm << "  IoU " << reg.iou;
  cv::putText(out, text.str(), cv::Point(10, 10 + static_cast<int>(25 * fontScale)),
              cv::FONT_HERSHEY_SIMPLEX, fontScale, cv::Scalar(0, 0, 255), 1);
  return out;
}

// ---------------------------------------------------------------------------------------------
// Calibration JSON

Calibration makeCalibration(const FormModel& form, const Registration& reg,
                            const std::filesystem::path& formSidecar,
                            const std::filesystem::path& emptyFrame,
                            const std::optional<CameraModel>& camera) {
  Calibration c;
  c.formSidecar = formSidecar;
  c.camera = camera;
  c.emptyFrame = emptyFrame;
  c.imageSize = reg.imageSize;
  c.pose = reg.pose;
  c.iou = reg.iou;
  c.landmarks = reg.landmarks;
  c.landmarkHeightsCm = form.landmarks().toMap();
  c.frameBottomCm = reg.frameBottomCm;
  return c;
}

namespace {
using nlohmann::json;
double r4(double v) {
  return std::round(v * 1e4) / 1e4;
}
}  // namespace

std::string calibrationToJson(const Calibration& c) {
  json j;
  j["version"] = 1;
  j["units"] = "cm";
  j["form"] = c.formSidecar.string();
  j["empty_frame"] = c.emptyFrame.string();
  j["image_size"] = {c.imageSize.width, c.imageSize.height};
  j["camera"] = c.camera ? json::parse(cameraToJson(*c.camera)) : json(nullptr);
  json pose;
  pose["projection"] = c.pose.perspective ? "perspective" : "orthographic";
  pose["px_per_cm"] = r4(c.pose.pxPerCm);
  pose["offset_px"] = {r4(c.pose.offsetPx.x()), r4(c.pose.offsetPx.y())};
  pose["roll_deg"] = r4(c.pose.rollRad * 180 / std::numbers::pi);
  if (c.pose.perspective) {
    const Intrinsics& k = *c.pose.perspective;
    pose["intrinsics"] = {{"fx", k.fx}, {"fy", k.fy}, {"cx", k.cx}, {"cy", k.cy}};
    pose["distance_cm"] = r4(*c.pose.distanceCm());
  }
  j["pose"] = pose;
  j["fit"] = {{"iou", r4(c.iou)}};
  j["landmarks_px"] = json::object();
  for (const auto& [name, p] : c.landmarks)
    j["landmarks_px"][name] = {r4(p.x()), r4(p.y())};
  j["landmark_heights_cm"] = json::object();
  for (const auto& [name, h] : c.landmarkHeightsCm)
    j["landmark_heights_cm"][name] = r4(h);
  j["frame_bottom_cm"] = c.frameBottomCm ? json(r4(*c.frameBottomCm)) : json(nullptr);
  return j.dump(2) + "\n";
}

void writeCalibration(const std::filesystem::path& path, const Calibration& c) {
  drafts::writeFileAtomic(path, calibrationToJson(c));
}

Calibration readCalibration(const std::filesystem::path& path) {
  return calibrationFromJson(drafts::readJsonFile(path), path.string());
}

Calibration calibrationFromJson(const nlohmann::json& j, const std::string& what) {
  using drafts::ParseError;
  static const std::set<std::string> kKnown = {
      "version", "units", "form",         "empty_frame",         "image_size",     "camera",
      "pose",    "fit",   "landmarks_px", "landmark_heights_cm", "frame_bottom_cm"};
  if (!j.is_object())
    throw ParseError(what + ": calibration must be a JSON object");
  for (const auto& [k, v] : j.items()) {
    if (!kKnown.count(k))
      throw ParseError(what + ": unknown field '" + k + "'");
  }
  if (drafts::requireNumber(j, "version", what) != 1) {
    throw ParseError(what + ": field 'version' must be 1");
  }
  if (drafts::requireString(j, "units", what) != "cm") {
    throw ParseError(what + ": field 'units' must be \"cm\"");
  }
  Calibration c;
  c.formSidecar = drafts::requireString(j, "form", what);
  c.emptyFrame = drafts::requireString(j, "empty_frame", what);
  const json& size = drafts::requireField(j, "image_size", what);
  if (!size.is_array() || size.size() != 2 || !size[0].is_number_integer() ||
      !size[1].is_number_integer()) {
    throw ParseError(what + ": field 'image_size' must be [width, height]");
  }
  c.imageSize = {size[0].get<int>(), size[1].get<int>()};
  const json& cam = drafts::requireField(j, "camera", what);
  if (!cam.is_null()) {
    c.camera = cameraFromJson(cam, what + ": camera");
  }
  const json& pose = drafts::requireField(j, "pose", what);
  const std::string w = what + ": pose";
  const std::string projection = drafts::requireString(pose, "projection", w);
  c.pose.pxPerCm = drafts::requireNumber(pose, "px_per_cm", w);
  const json& off = drafts::requireField(pose, "offset_px", w);
  if (!off.is_array() || off.size() != 2 || !off[0].is_number() || !off[1].is_number()) {
    throw ParseError(w + ": field 'offset_px' must be [x, y]");
  }
  c.pose.offsetPx = {off[0].get<double>(), off[1].get<double>()};
  c.pose.rollRad = drafts::requireNumber(pose, "roll_deg", w) * std::numbers::pi / 180;
  if (projection == "perspective") {
    const json& k = drafts::requireField(pose, "intrinsics", w);
    const std::string wk = w + ".intrinsics";
    c.pose.perspective =
        Intrinsics{drafts::requireNumber(k, "fx", wk), drafts::requireNumber(k, "fy", wk),
                   drafts::requireNumber(k, "cx", wk), drafts::requireNumber(k, "cy", wk)};
  } else if (projection != "orthographic") {
    throw ParseError(w + ": field 'projection' must be \"orthographic\" or \"perspective\"");
  }
  if (!(c.pose.pxPerCm > 0))
    throw ParseError(w + ": field 'px_per_cm' must be positive");
  c.iou = drafts::requireNumber(drafts::requireField(j, "fit", what), "iou", what + ": fit");
  const json& lm = drafts::requireField(j, "landmarks_px", what);
  if (!lm.is_object())
    throw ParseError(what + ": field 'landmarks_px' must be an object");
  for (const auto& [name, p] : lm.items()) {
    if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number()) {
      throw ParseError(what + ": landmarks_px." + name + " must be [x, y]");
    }
    c.landmarks.emplace_back(name, Eigen::Vector2d(p[0].get<double>(), p[1].get<double>()));
  }
  const json& lh = drafts::requireField(j, "landmark_heights_cm", what);
  if (!lh.is_object())
    throw ParseError(what + ": field 'landmark_heights_cm' must be an object");
  for (const auto& [name, h] : lh.items()) {
    if (!h.is_number())
      throw ParseError(what + ": landmark_heights_cm." + name + " must be a number");
    c.landmarkHeightsCm[name] = h.get<double>();
  }
  // Optional (calibrations before it had none): null or absent when the whole form is in view.
  if (const auto it = j.find("frame_bottom_cm"); it != j.end() && !it->is_null()) {
    if (!it->is_number())
      throw ParseError(what + ": field 'frame_bottom_cm' must be a number or null");
    c.frameBottomCm = it->get<double>();
  }
  return c;
}

}  // namespace garmcap::calib
