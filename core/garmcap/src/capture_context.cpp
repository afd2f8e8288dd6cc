#include "garmcap/pipeline/capture_context.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "garmcap/drafts/size_charts.h"
#include "garmcap/pipeline/reference_garment.h"

namespace garmcap::pipeline {
namespace {

// Height of the form view the reference silhouettes are drawn on (the classifier works at 320).
constexpr double kReferenceHeightPx = 640.0;

// One garment per type and attributes at three lengths, so that the database covers the lengths
// garments come in.
struct Variant {
  std::string type;
  std::map<std::string, std::string> attributes;
  double lengthFactor;
};

std::vector<Variant> variants() {
  std::vector<Variant> v;
  for (double f : {0.6, 1.0, 1.4}) {
    for (const char* sleeve : {"none", "short", "long"}) {
      v.push_back({"top", {{"sleeve", sleeve}}, f});
      for (const char* skirt : {"a_line", "h_line"})
        v.push_back({"dress", {{"sleeve", sleeve}, {"skirt", skirt}}, f});
    }
    for (const char* skirt : {"a_line", "h_line"})
      v.push_back({"skirt", {{"skirt", skirt}}, f});
    v.push_back({"pants", {}, f});
  }
  return v;
}

}  // namespace

drafts::Measurements bodyForForm(const calib::FormModel& form, const drafts::SizeChart& chart) {
  const double bust = form.measurements().find("bust_circ").value_or(0);
  std::size_t best = 0;
  for (std::size_t i = 1; i < chart.bodies.size(); ++i)
    if (std::abs(chart.bodies[i].get("bust_circ") - bust) <
        std::abs(chart.bodies[best].get("bust_circ") - bust))
      best = i;
  drafts::Measurements body = chart.bodies[best];
  for (const auto& [name, value] : form.measurements().values())
    if (drafts::isKnownMeasurement(name))
      body.set(name, value);
  return body;
}

std::vector<ReferenceSilhouette> renderReferenceSilhouettes(const FormView& view,
                                                            const drafts::Measurements& body) {
  std::vector<ReferenceSilhouette> refs;
  for (const auto& v : variants()) {
    if (v.type == "pants" && !view.crotchCm())
      continue;  // a form without legs wears no pants
    if (v.attributes.count("sleeve") && v.attributes.at("sleeve") != "none" && !view.arm(0) &&
        !view.arm(1))
      continue;
    try {
      const ReferenceGarment garment =
          referenceGarment(v.type, v.attributes, v.lengthFactor, body, view);
      refs.push_back({v.type, v.attributes, drawReferenceGarment(garment, view)});
    } catch (const std::exception& e) {
      // A reference that cannot be drawn would silently take its type or cut out of the
      // classifier (three long tops did, on every bundled form): the calibration is refused.
      std::string what = v.type;
      for (const auto& [k, a] : v.attributes)
        what += " " + k + "=" + a;
      throw std::runtime_error("the classifier's reference " + what + " (length x" +
                               std::to_string(v.lengthFactor).substr(0, 3) +
                               ") cannot be drawn on this form: " + e.what());
    }
  }
  return refs;
}

std::shared_ptr<const CaptureContext> buildCaptureContext(const nlohmann::json& calibration,
                                                          const std::string& sizeChart) {
  auto ctx = std::make_shared<CaptureContext>();
  ctx->sizeChart = sizeChart;
  ctx->calibration = calib::calibrationFromJson(calibration, "calibration");
  if (const auto& camera = ctx->calibration.camera) {
    if (camera->imageSize != ctx->calibration.imageSize)
      throw std::invalid_argument(
          "the camera model is for " + std::to_string(camera->imageSize.width) + "x" +
          std::to_string(camera->imageSize.height) + " frames but the calibration is for " +
          std::to_string(ctx->calibration.imageSize.width) + "x" +
          std::to_string(ctx->calibration.imageSize.height));
    ctx->undistorter = std::make_shared<const calib::FrameUndistorter>(*camera);
  }
  ctx->form = std::make_shared<const calib::FormModel>(
      calib::FormModel::load(ctx->calibration.formSidecar));
  calib::FormPose upright = ctx->calibration.pose;
  upright.rollRad = 0;  // frames are de-rolled about the world origin's image position
  ctx->view = std::make_shared<const FormView>(*ctx->form, upright, ctx->calibration.imageSize);
  ctx->depthTable = formDepthTable(*ctx->view);
  ctx->body = bodyForForm(*ctx->form, drafts::sizeChart(sizeChart));
  // The classifier compares silhouettes a few hundred rows high, so the references are drawn on
  // the form seen at about that size, not at the camera's: at 12 MP drawing every reference
  // garment at full size took most of a minute per calibration on 2 cores.
  const double f = std::min(1.0, kReferenceHeightPx / ctx->calibration.imageSize.height);
  const FormView* refView = ctx->view.get();
  std::optional<FormView> smallView;
  if (f < 1.0) {
    calib::FormPose small = upright;
    small.pxPerCm *= f;
    small.offsetPx *= f;
    if (small.perspective) {
      small.perspective->fx *= f;
      small.perspective->fy *= f;
      small.perspective->cx *= f;
      small.perspective->cy *= f;
    }
    const cv::Size smallSize(
        std::max(1, static_cast<int>(std::lround(ctx->calibration.imageSize.width * f))),
        std::max(1, static_cast<int>(std::lround(ctx->calibration.imageSize.height * f))));
    refView = &smallView.emplace(*ctx->form, small, smallSize);
  }
  // A frame that cuts the form's legs (frame_bottom_cm) would cut the references' legs too: the
  // pants' hem and the long skirts have no form to be laid on there, and those references were
  // lost. They are laid on the frame extended down to the floor and cut back to the frame's rows
  // (a reference that leaves the frame is cut like a garment that did would be, and no garment
  // that does is measured).
  const int refRows = refView->size().height;
  std::optional<FormView> tallView;
  if (ctx->calibration.frameBottomCm) {
    const calib::FormPose& p = refView->pose();
    const double floorRow =
        calib::projectPoint(p, {ctx->form->axisXCm(), ctx->form->minYCm(), 0}).y();
    const int rows = static_cast<int>(std::ceil(floorRow + 0.05 * refRows));
    if (rows > refRows)
      refView = &tallView.emplace(*ctx->form, p, cv::Size(refView->size().width, rows));
  }
  std::vector<ReferenceSilhouette> refs = renderReferenceSilhouettes(*refView, ctx->body);
  if (tallView) {
    for (auto& r : refs)
      r.mask = r.mask(cv::Rect(0, 0, r.mask.cols, refRows)).clone();
    std::erase_if(refs, [](const ReferenceSilhouette& r) { return cv::countNonZero(r.mask) == 0; });
  }
  ctx->classifier = std::make_shared<const GarmentClassifier>(std::move(refs));
  return ctx;
}

}  // namespace garmcap::pipeline
