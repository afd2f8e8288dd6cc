// garmcap capture / garmcap rig eval: the GarmCap pipeline (core/garmcap) on a photo pair or a rig.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <string_view>
#include <utility>

#include "commands.h"
#include "garmcap/calib/camera.h"
#include "garmcap/calib/form_model.h"
#include "garmcap/calib/registration.h"
#include "garmcap/capture/rig.h"
#include "garmcap/drafts/file_io.h"
#include "garmcap/drafts/pattern_io.h"
#include "garmcap/drafts/svg.h"
#include "garmcap/pipeline/capture_context.h"
#include "garmcap/pipeline/capture_pipeline.h"
#include "garmcap/pipeline/image_files.h"

namespace garmcap::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

void writeImage(const fs::path& path, const cv::Mat& img) {
  if (img.empty())
    return;
  std::vector<uchar> bytes;
  const std::string ext = path.extension().string();
  std::vector<int> params;
  if (ext == ".jpg")
    params = {cv::IMWRITE_JPEG_QUALITY, 90};
  if (!cv::imencode(ext, img, bytes, params))
    throw drafts::FileError("cannot encode " + path.string());
  drafts::writeFileAtomic(
      path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

void writeCaptureOutputs(const fs::path& out, const pipeline::CaptureResult& r) {
  fs::create_directories(out);
  drafts::writeJsonFile(out / "result.json", r.toJson());
  if (!r.pattern.panels.empty()) {
    drafts::writePatternJson(out / "pattern.json", r.pattern);
    drafts::writePatternSvg(out / "pattern.svg", r.pattern);
  }
  // Encoded as the station stores them (image_files.h): the shop photos as JPEG and WebP.
  const std::vector<std::pair<std::string, cv::Mat>> images = {
      {"cutout", r.cutout},
      {"product", r.product},
      {"product_4x5", r.productPortrait},
      {"silhouette", r.silhouette},
      {"overlay", r.overlay},
      {"texture", r.texture},
      {"cutout_back", r.backCutout},
      {"product_back", r.backProduct},
      {"product_back_4x5", r.backProductPortrait},
      {"product_ghost", r.ghostProduct},
      {"product_ghost_4x5", r.ghostProductPortrait}};
  for (const pipeline::EncodedImage& e : pipeline::encodeImageSet(images))
    drafts::writeFileAtomic(out / e.fileName, e.bytes);
}

// Per measurement: the absolute errors of the readings taken and the readings missing (a truth
// measurement the pipeline did not report, or a case that failed). A missing reading is a
// failure: leaving out a hard reading must never improve the table.
struct ErrorStats {
  double sum = 0, max = 0;
  int n = 0, missing = 0;
  void add(double e) {
    sum += std::abs(e);
    max = std::max(max, std::abs(e));
    ++n;
  }
  double missingRate() const {
    return n + missing ? static_cast<double>(missing) / (n + missing) : 0;
  }
  json toJson() const {
    return {{"mean_abs_cm", n ? sum / n : 0.0},
            {"max_abs_cm", max},
            {"n", n},
            {"missing", missing},
            {"missing_rate", missingRate()}};
  }
};

// Which cases an evaluation runs: all, or the even- or odd-numbered ones (by their position in
// rig.json), so that a method can be tuned on one half and checked on the other.
enum class CaseSplit { kAll, kEven, kOdd };

// Whether a truth reading is one the station owes. A sleeveless garment's sleeve_length (truth 0)
// on a form without arms is not: the station does not read sleeves on an armless form (a sleeve
// has no arm to give it a direction or an end; docs/measurement_model.md "Torso forms"), and a
// sleeveless truth left unread is the right answer, not a missing one. A sleeve (truth > 0) on
// an armless form is still owed, and missing when it is not read.
bool readingOwed(const std::string& name, double truth, bool formHasArms) {
  return formHasArms || name != "sleeve_length" || truth != 0.0;
}

// The calibration a station would have for a case: the form registered from the case's bare
// frame the way `garmcap calibrate` does it, never the scene's pose. The case's calibration.json
// gives what a station knows before registering: the form, the camera model (or the case's
// camera.json) and, for a perspective fit, the camera's distance. One evaluation keeps the
// registrations it made by the bare frame's pixels, as the cases of one session share their bare
// frame.
class StationCalibrations {
 public:
  const json& of(const capture::RigCase& c);

 private:
  std::map<std::size_t, json> byBareFrame_;
};

const json& StationCalibrations::of(const capture::RigCase& c) {
  const json& given = c.calibration;
  if (!given.is_object() || !given.contains("form") || !given["form"].is_string())
    throw std::runtime_error("case has no calibration.json naming its form");
  std::optional<calib::CameraModel> camera;
  if (given.contains("camera") && given["camera"].is_object())
    camera = calib::cameraFromJson(given["camera"], c.id + " calibration.json: camera");
  else if (fs::exists(c.dir / "camera.json"))
    camera = calib::readCameraJson(c.dir / "camera.json");
  calib::RegistrationOptions options;
  if (camera) {
    options.intrinsics = camera->intrinsics();
    const json pose = given.value("pose", json::object());
    if (pose.contains("distance_cm"))
      options.distanceCm = pose["distance_cm"].get<double>();
  }
  const cv::Mat empty = camera ? calib::undistortFrame(c.empty, *camera) : c.empty;
  const cv::Mat contiguous = empty.isContinuous() ? empty : empty.clone();
  std::size_t key = std::hash<std::string_view>{}(std::string_view(
      reinterpret_cast<const char*>(contiguous.data), contiguous.total() * contiguous.elemSize()));
  key ^= std::hash<std::string>{}(given["form"].get<std::string>() +
                                  (camera ? calib::cameraToJson(*camera) : "") +
                                  std::to_string(options.distanceCm.value_or(0)));
  if (const auto it = byBareFrame_.find(key); it != byBareFrame_.end())
    return it->second;
  const fs::path formPath = calib::resolveFormSidecar(given["form"].get<std::string>());
  const auto form = calib::FormModel::load(formPath);
  const calib::Registration reg =
      calib::registerForm(form, cv::Mat3b(empty), c.id + " bare-form frame", options);
  const calib::Calibration cal =
      calib::makeCalibration(form, reg, formPath, c.dir / "empty.jpg", camera);
  return byBareFrame_[key] = json::parse(calib::calibrationToJson(cal));
}

// The capture contexts of one evaluation, one per calibration (the cases of a session share
// theirs), built with `sizeChart` as a station would build it at its calibration.
class EvalContexts {
 public:
  explicit EvalContexts(std::string sizeChart) : sizeChart_(std::move(sizeChart)) {}
  std::shared_ptr<const pipeline::CaptureContext> of(const json& calibration) {
    auto& ctx = byCalibration_[calibration.dump()];
    if (!ctx) {
      try {
        ctx = pipeline::buildCaptureContext(calibration, sizeChart_);
      } catch (const std::exception& e) {
        throw pipeline::CaptureError(pipeline::CaptureError::Reason::kBadInput,
                                     std::string("calibration: ") + e.what());
      }
    }
    return ctx;
  }

 private:
  std::string sizeChart_;
  std::map<std::string, std::shared_ptr<const pipeline::CaptureContext>> byCalibration_;
};

// How the station's registration differs from the case's own calibration.json (the scene's pose
// for a simulated rig): scale in percent, offset in px.
json registrationScore(const json& registered, const json& given) {
  const json& a = registered.at("pose");
  const json& b = given.value("pose", json::object());
  if (!b.contains("px_per_cm") || !b.contains("offset_px"))
    return nullptr;
  const double scalePct =
      100.0 * (a.at("px_per_cm").get<double>() / b["px_per_cm"].get<double>() - 1.0);
  const double dx = a.at("offset_px")[0].get<double>() - b["offset_px"][0].get<double>();
  const double dy = a.at("offset_px")[1].get<double>() - b["offset_px"][1].get<double>();
  return {{"px_per_cm_pct", std::round(scalePct * 1000) / 1000},
          {"offset_px", std::round(std::hypot(dx, dy) * 100) / 100}};
}

void printTable(const std::map<std::string, ErrorStats>& errors) {
  std::printf("%-18s %7s %7s %4s %8s %8s\n", "measurement", "mean", "max", "n", "missing",
              "missing%");
  for (const auto& [k, s] : errors)
    std::printf("%-18s %7.2f %7.2f %4d %8d %7.0f%%\n", k.c_str(), s.n ? s.sum / s.n : 0.0, s.max,
                s.n, s.missing, 100.0 * s.missingRate());
}

int rigEval(const fs::path& rigDir, const fs::path& outDir, bool compareMethods,
            double workMegapixels, bool useCaseCalibration, CaseSplit split,
            const std::string& sizeChart) {
  const capture::Rig rig = capture::readRig(rigDir);
  StationCalibrations stationCalibrations;
  EvalContexts contexts(sizeChart);
  std::map<std::string, ErrorStats> errors;
  int typeOk = 0, attrOk = 0, attrN = 0, failures = 0, n = 0, missing = 0, notOwed = 0;
  double totalMs = 0;
  std::map<std::string, std::pair<int, double>> methodStats;  // method -> (correct, ms)
  json cases = json::array();
  for (std::size_t index = 0; index < rig.cases.size(); ++index) {
    if ((split == CaseSplit::kEven && index % 2 != 0) ||
        (split == CaseSplit::kOdd && index % 2 != 1))
      continue;
    ++n;
    const auto& info = rig.cases[index];
    const capture::RigCase c = capture::loadRigCase(info.dir);
    json row = {{"id", c.id}, {"truth_type", c.truth.value("type", "")}};
    const json& tm = c.truth.value("measurements", json::object());
    try {
      if (c.calibration.is_null())
        throw std::runtime_error("case has no calibration");
      const json calibration = useCaseCalibration ? c.calibration : stationCalibrations.of(c);
      if (!useCaseCalibration)
        row["registration"] = registrationScore(calibration, c.calibration);
      pipeline::CaptureOptions opt;
      opt.makeTexture = !outDir.empty();
      opt.makeProductImages = !outDir.empty();
      opt.workMegapixels = workMegapixels;
      // Timed with the preparation, as a station's first capture after its calibration.
      const auto t0 = std::chrono::steady_clock::now();
      const auto ctx = contexts.of(calibration);
      const pipeline::PreparedCapture prepared(ctx, c.empty, workMegapixels);
      const auto r = pipeline::runCapture(prepared, c.dressed, opt);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      totalMs += ms;
      row["type"] = r.type;
      row["ms"] = std::round(ms);
      if (r.type == c.truth.value("type", ""))
        ++typeOk;
      const json& ta = c.truth.value("attributes", json::object());
      for (const auto& [k, v] : ta.items()) {
        ++attrN;
        const auto it = r.attributes.find(k);
        if (it != r.attributes.end() && it->second == v.get<std::string>())
          ++attrOk;
        else
          row["attribute_miss"][k] = it == r.attributes.end() ? "missing" : it->second;
      }
      const bool formHasArms = ctx->view && (ctx->view->arm(0) || ctx->view->arm(1));
      for (const auto& [k, v] : tm.items()) {
        const auto it = r.measurements.find(k);
        if (it == r.measurements.end() && !readingOwed(k, v.get<double>(), formHasArms)) {
          row["not_owed"].push_back(k);
          ++notOwed;
          continue;
        }
        if (it == r.measurements.end()) {
          row["missing"].push_back(k);
          ++errors[k].missing;
          ++missing;
          continue;
        }
        const double e = it->second - v.get<double>();
        errors[k].add(e);
        row["error_cm"][k] = std::round(e * 100) / 100;
      }
      if (!r.warnings.empty())
        row["warnings"] = r.warnings;
      if (!outDir.empty())
        writeCaptureOutputs(outDir / c.id, r);
      if (compareMethods) {
        // Same silhouette, every classifier: which ranks types best, and at what cost.
        for (auto m : {pipeline::MatchMethod::kIou, pipeline::MatchMethod::kChamfer,
                       pipeline::MatchMethod::kShapeContext}) {
          const auto m0 = std::chrono::steady_clock::now();
          const auto cls = ctx->classifier->classify(r.silhouette, m);
          const double mms =
              std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - m0)
                  .count();
          auto& st = methodStats[pipeline::toString(m)];
          st.first += cls.type == c.truth.value("type", "") ? 1 : 0;
          st.second += mms;
        }
      }
    } catch (const std::exception& e) {
      ++failures;
      row["error"] = e.what();
      // Every reading of a failed case is missing.
      for (const auto& [k, v] : tm.items()) {
        ++errors[k].missing;
        ++missing;
      }
    }
    std::cout << row.dump() << "\n";
    cases.push_back(row);
  }
  int readings = missing;
  for (const auto& [k, s] : errors)
    readings += s.n;
  json summary = {{"cases", n},
                  {"failures", failures},
                  {"calibration",
                   useCaseCalibration ? "case calibration.json" : "registered from the bare frame"},
                  {"type_accuracy", n ? static_cast<double>(typeOk) / n : 0.0},
                  {"attribute_accuracy", attrN ? static_cast<double>(attrOk) / attrN : 1.0},
                  {"readings", readings},
                  {"readings_missing", missing},
                  {"readings_not_owed", notOwed},
                  {"ms_per_case", n - failures > 0 ? totalMs / (n - failures) : 0.0}};
  for (const auto& [k, s] : errors)
    summary["measurements"][k] = s.toJson();
  for (const auto& [m, st] : methodStats)
    summary["classifiers"][m] = {{"type_accuracy", n ? static_cast<double>(st.first) / n : 0.0},
                                 {"ms_per_case", n ? st.second / n : 0.0}};
  std::cout << json({{"summary", summary}}).dump(2) << "\n";
  std::printf("%d cases (%d failed): types %d/%d, attributes %d/%d, %d of %d readings missing\n", n,
              failures, typeOk, n, attrOk, attrN, missing, readings);
  if (notOwed > 0)
    std::printf("%d sleeveless truths on an armless form not counted (no sleeve is read there)\n",
                notOwed);
  printTable(errors);
  if (!outDir.empty())
    drafts::writeJsonFile(outDir / "eval.json", {{"summary", summary}, {"cases", cases}});
  return failures == 0 ? 0 : 1;
}

// The frame row where a case's form is `heightCm` high on its axis, from the case's own
// calibration (for a simulated rig the scene's pose). Only chooses where to cut: it is the raw
// frame's row up to the lens distortion, which moves it by a few px at the frame's edge.
int rowOfFormHeight(const capture::RigCase& c, double heightCm) {
  const calib::Calibration cal = calib::calibrationFromJson(c.calibration, c.id + " calibration");
  return static_cast<int>(std::floor(calib::projectPoint(cal.pose, {0, heightCm, 0}).y()));
}

// `garmcap rig crop`: the rig as a station framing the garment sees it, the form cut at
// `atCm` on the form (legs, feet, stand below the frame). Only cases whose garment ends at
// least `marginCm` above the cut are kept (truth's garment_heights_cm.hem); frames are written
// as PNG so the cut adds no second JPEG compression.
void rigCrop(const fs::path& rigDir, const fs::path& outDir, double atCm, double marginCm) {
  const capture::Rig rig = capture::readRig(rigDir);
  json index = rig.index;
  index["cases"] = json::array();
  index["image_format"] = "png";
  index.erase("jpeg_quality");
  index.erase("height");
  char what[96];
  std::snprintf(what, sizeof what, ", its frames cut at %.1f cm on the form (garmcap rig crop)",
                atCm);
  index["generator"] = index.value("generator", std::string("?")) + what;
  if (index.contains("form") && index["form"].is_string() &&
      fs::path(index["form"].get<std::string>()).is_relative())
    index["form"] =
        fs::absolute(rigDir / index["form"].get<std::string>()).lexically_normal().string();
  int kept = 0;
  for (std::size_t i = 0; i < rig.cases.size(); ++i) {
    const auto& info = rig.cases[i];
    const capture::RigCase c = capture::loadRigCase(info.dir);
    const json heights = c.truth.value("garment_heights_cm", json::object());
    if (!heights.contains("hem") || !heights["hem"].is_number())
      throw std::runtime_error(info.dir.string() + "/truth.json: no garment_heights_cm.hem");
    const double hem = heights["hem"].get<double>();
    if (hem < atCm + marginCm) {
      std::printf("%s: skipped (hem at %.1f cm, below %.1f + %.1f cm)\n", c.id.c_str(), hem, atCm,
                  marginCm);
      continue;
    }
    const int row = rowOfFormHeight(c, atCm);
    if (row >= c.empty.rows) {
      std::printf("%s: skipped (%.1f cm is below the frame)\n", c.id.c_str(), atCm);
      continue;
    }
    capture::RigCase cut = capture::cropRigCaseBottom(c, row);
    // loadRigCase resolved the form against the case folder; the new case lives elsewhere.
    if (cut.calibration.contains("form") && cut.calibration["form"].is_string())
      cut.calibration["form"] =
          fs::absolute(cut.calibration["form"].get<std::string>()).lexically_normal().string();
    const fs::path dir = outDir / info.dir.filename();
    fs::create_directories(dir);
    const capture::RigImageOptions png{capture::RigImageFormat::kPng};
    capture::writeRigFrame(dir, "empty", cut.empty, png);
    capture::writeRigFrame(dir, "dressed", cut.dressed, png);
    drafts::writeJsonFile(dir / "truth.json", cut.truth);
    drafts::writeJsonFile(dir / "calibration.json", cut.calibration);
    if (fs::exists(c.dir / "camera.json"))
      drafts::writeJsonFile(dir / "camera.json", cut.calibration["camera"]);
    json entry = rig.index["cases"][i];
    entry["dir"] = info.dir.filename().string();
    index["cases"].push_back(entry);
    ++kept;
    std::printf("%s: %d of %d rows kept (hem at %.1f cm)\n", c.id.c_str(), row, c.empty.rows, hem);
  }
  drafts::writeJsonFile(outDir / "rig.json", index);
  std::printf("%s: %d of %zu cases, rig.json written\n", outDir.c_str(), kept, rig.cases.size());
}

}  // namespace

cv::Mat readFrameFile(const fs::path& path, const std::string& what) {
  try {
    return capture::loadRigImage(path);
  } catch (const capture::RigError& e) {
    throw drafts::FileError(what + ": " + e.what());
  }
}

void addPipelineCommands(CLI::App& app, CLI::App& rigGroup) {
  auto* cap = app.add_subcommand("capture", "Run GarmCap on a bare-form and a dressed frame");
  static fs::path empty, dressed, calibration, out, back;
  static std::string captureChart = pipeline::kDefaultSizeChart;
  static bool productShadow = false;
  cap->add_option("--empty", empty, "bare-form frame (PNG/JPEG)")->required();
  cap->add_option("--dressed", dressed, "dressed frame, same camera and size")->required();
  cap->add_option("--calibration", calibration, "calibration JSON (garmcap calibrate)")->required();
  cap->add_option("--out", out, "output folder")->required();
  cap->add_option("--size-chart", captureChart,
                  "size chart completing the form's body for drafting (default korean_women, as "
                  "the daemon's [pipeline] size_chart)");
  cap->add_option("--back", back,
                  "back shot: the same garment turned back to front on the form, same camera; "
                  "adds the back photos (product_back*, cutout_back) and the ghost-mannequin "
                  "front (product_ghost*)");
  cap->add_flag("--product-shadow", productShadow,
                "a soft drop shadow under the garment on the white photos (product, product_4x5; "
                "as the daemon's [pipeline] product_shadow)");
  cap->callback([] {
    const cv::Mat e = readFrameFile(empty, "bare-form frame");
    const cv::Mat d = readFrameFile(dressed, "dressed frame");
    const json cal = drafts::readJsonFile(calibration);
    pipeline::CaptureOptions options;
    options.sizeChart = captureChart;
    options.productShadow = productShadow;
    if (!back.empty())
      options.backFrame = readFrameFile(back, "back shot");
    const auto r = pipeline::runCapture(e, d, cal, options);
    writeCaptureOutputs(out, r);
    std::cout << r.toJson().dump(2) << "\n";
  });

  CLI::App* rig = &rigGroup;
  auto* crop = rig->add_subcommand(
      "crop", "Cut a rig's frames at a height on the form, as a station framing the garment");
  static fs::path cropIn, cropOut;
  static double cropAtCm = 40, cropMarginCm = 5;
  crop->add_option("rig", cropIn, "rig folder (with rig.json)")->required();
  crop->add_option("--out", cropOut, "rig folder to write")->required();
  crop->add_option("--at-cm", cropAtCm,
                   "form height (cm, on its axis) at the new frame's bottom edge (default 40)");
  crop->add_option("--margin-cm", cropMarginCm,
                   "keep only cases whose hem is this far above the cut (default 5)");
  crop->callback([] { rigCrop(cropIn, cropOut, cropAtCm, cropMarginCm); });

  auto* eval = rig->add_subcommand(
      "eval", "Run the pipeline on every case of a rig and score it against truth.json");
  static fs::path rigDir, evalOut;
  static bool compare = false;
  eval->add_option("rig", rigDir, "rig folder (with rig.json)")->required();
  eval->add_option("--out", evalOut, "write each case's outputs and eval.json here");
  eval->add_flag("--compare-classifiers", compare,
                 "also time and score IoU, chamfer and Shape Context");
  static double workMp = pipeline::CaptureOptions{}.workMegapixels;
  eval->add_option("--work-mp", workMp,
                   "segment frames on a copy of about this many megapixels (default 2; a large "
                   "value segments at full resolution)")
      ->check(CLI::PositiveNumber);
  static bool caseCalibration = false;
  eval->add_flag("--case-calibration", caseCalibration,
                 "use each case's calibration.json as it is (for a simulated rig: the scene's "
                 "true pose) instead of registering the form from the case's bare frame");
  static std::string splitName = "all";
  eval->add_option("--cases", splitName,
                   "all, or only the even- or odd-numbered cases (tune on one, hold out the other)")
      ->check(CLI::IsMember({"all", "even", "odd"}));
  static std::string evalChart = pipeline::kDefaultSizeChart;
  eval->add_option("--size-chart", evalChart,
                   "size chart completing the form's body for drafting (default korean_women)");
  static fs::path refsOut;
  eval->add_option("--dump-references", refsOut,
                   "write the type database's silhouettes of the first case here");
  eval->callback([] {
    if (!refsOut.empty()) {
      const auto rig = capture::readRig(rigDir);
      const auto c = capture::loadRigCase(rig.cases.front().dir);
      const auto ctx = pipeline::buildCaptureContext(c.calibration, evalChart);
      fs::create_directories(refsOut);
      const auto refs = pipeline::renderReferenceSilhouettes(*ctx->view, ctx->body);
      for (std::size_t i = 0; i < refs.size(); ++i) {
        std::string name = std::to_string(i) + "_" + refs[i].type;
        for (const auto& [k, v] : refs[i].attributes)
          name += "_" + v;
        writeImage(refsOut / (name + ".png"), refs[i].mask);
      }
    }
    const CaseSplit split = splitName == "even"  ? CaseSplit::kEven
                            : splitName == "odd" ? CaseSplit::kOdd
                                                 : CaseSplit::kAll;
    const int rc = rigEval(rigDir, evalOut, compare, workMp, caseCalibration, split, evalChart);
    if (rc != 0)
      throw std::runtime_error("some rig cases failed (see their \"error\")");
  });
}

}  // namespace garmcap::cli
