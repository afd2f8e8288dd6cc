#pragma once
// Everything GarmCap needs that depends only on the calibration, built once per calibration and
// shared by every capture made with it: the form model, the form's geometry in the image (pose
// without roll; frames are de-rolled first), the body the form stands for, and the reference
// silhouettes of known garments rendered from the project's drafts on this form (type database).

#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "garmcap/calib/camera.h"
#include "garmcap/calib/form_model.h"
#include "garmcap/calib/registration.h"
#include "garmcap/drafts/measurements.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/pipeline/garment_classifier.h"
#include "garmcap/pipeline/garment_measurer.h"

namespace garmcap::pipeline {

struct CaptureContext {
  calib::Calibration calibration;
  // The calibration's camera model as pixel maps, computed once: the bare frame was undistorted
  // with it before the form was registered, so both frames of a capture are too. Null without a
  // camera model (the frames are used as they are).
  std::shared_ptr<const calib::FrameUndistorter> undistorter;
  std::shared_ptr<const calib::FormModel> form;
  std::shared_ptr<const FormView> view;  // form seen with the calibrated pose, roll removed
  drafts::Measurements body;             // the form's measurements completed from a size chart
  std::shared_ptr<const GarmentClassifier> classifier;
  // The form's depth table for the measurer, made here so the first capture does not pay for
  // slicing the form; held so it stays while the context does.
  std::shared_ptr<const FormDepthTable> depthTable;
  // The size chart whose nearest size completes the form's body (bodyForForm).
  std::string sizeChart;
};

/// The chart the station's configuration names when it names none ([pipeline] size_chart).
inline constexpr const char* kDefaultSizeChart = "korean_women";

/// Builds the context from calibration JSON (docs/formats.md), the form's body completed from
/// `sizeChart` (drafts::sizeCharts). It is built once per calibration and owned by whoever runs
/// captures with it. Throws drafts::ParseError for a malformed calibration, calib::CalibError for
/// a missing or bad form, std::invalid_argument for an unknown chart.
std::shared_ptr<const CaptureContext> buildCaptureContext(const nlohmann::json& calibration,
                                                          const std::string& sizeChart);

/// Reference silhouettes of every type and attribute combination at three lengths, drafted for
/// `body` by the project's recipes and drawn on the form by the pipeline's own reference garment
/// (reference_garment.h; it shares no model with the scene simulator). Throws
/// std::runtime_error naming the reference when one cannot be drawn on this form.
std::vector<ReferenceSilhouette> renderReferenceSilhouettes(const FormView& view,
                                                            const drafts::Measurements& body);

/// The form's own measurements completed, for names the form does not give, from the size of
/// `chart` whose bust is nearest (drafts need neck-to-waist, arm lengths, ...).
drafts::Measurements bodyForForm(const calib::FormModel& form, const drafts::SizeChart& chart);

}  // namespace garmcap::pipeline
