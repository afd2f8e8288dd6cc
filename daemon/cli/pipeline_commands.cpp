// garmcap capture / garmcap rig eval: the GarmCap pipeline (core/garmcap) on a photo pair or a rig.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>

#include "commands.h"
#include "garmcap/capture/rig.h"
#include "garmcap/drafts/file_io.h"
#include "garmcap/drafts/pattern_io.h"
#include "garmcap/drafts/svg.h"
#include "garmcap/pipeline/capture_context.h"
#include "garmcap/pipeline/capture_pipeline.h"

namespace garmcap::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

cv::Mat readImage(const fs::path& path, const std::string& what) {
  if (!fs::exists(path))
    throw drafts::FileError(what + " not found: " + path.string());
  cv::Mat img = cv::imread(path.string(), cv::IMREAD_COLOR);
  if (img.empty())
    throw drafts::FileError(what + " " + path.string() +
                            " is not a readable image (corrupt or truncated)");
  return img;
}

void writeImage(const fs::path& path, const cv::Mat& img) {
  if (img.empty())
    return;
  std::vector<uchar> bytes;
  const std::string ext = path.extension().string();
  std::vector<int> params;
  if (ext == ".jpg")
    params = {cv::IMWRITE_JPEG_QUALITY, 92};
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
  writeImage(out / "cutout.png", r.cutout);
  writeImage(out / "product.jpg", r.product);
  writeImage(out / "silhouette.png", r.silhouette);
  writeImage(out / "overlay.png", r.overlay);
  writeImage(out / "texture.png", r.texture);
}

struct ErrorStats {
  double sum = 0, max = 0;
  int n = 0;
  void add(double e) {
    sum += std::abs(e);
    max = std::max(max, std::abs(e));
    ++n;
  }
  json toJson() const {
    return {{"mean_abs_cm", n ? sum / n : 0.0}, {"max_abs_cm", max}, {"n", n}};
  }
};

int rigEval(const fs::path& rigDir, const fs::path& outDir, bool compareMethods,
            double workMegapixels) {
  const capture::Rig rig = capture::readRig(rigDir);
  std::map<std::string, ErrorStats> errors;
  int typeOk = 0, attrOk = 0, attrN = 0, failures = 0;
  double totalMs = 0;
  std::map<std::string, std::pair<int, double>> methodStats;  // method -> (correct, ms)
  json cases = json::array();
  for (const auto& info : rig.cases) {
    const capture::RigCase c = capture::loadRigCase(info.dir);
    json row = {{"id", c.id}, {"truth_type", c.truth.value("type", "")}};
    const auto t0 = std::chrono::steady_clock::now();
    try {
      if (c.calibration.is_null())
        throw std::runtime_error("case has no calibration");
      pipeline::CaptureOptions opt;
      opt.makeTexture = !outDir.empty();
      opt.makeProductImages = !outDir.empty();
      opt.workMegapixels = workMegapixels;
      const auto r = pipeline::runCapture(c.empty, c.dressed, c.calibration, opt);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      totalMs += ms;
      row["type"] = r.type;
      row["ms"] = ms;
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
      const json& tm = c.truth.value("measurements", json::object());
      for (const auto& [k, v] : tm.items()) {
        const auto it = r.measurements.find(k);
        if (it == r.measurements.end()) {
          row["missing"].push_back(k);
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
        const auto ctx = pipeline::cachedCaptureContext(c.calibration);
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
    }
    std::cout << row.dump() << "\n";
    cases.push_back(row);
  }
  const int n = static_cast<int>(rig.cases.size());
  json summary = {{"cases", n},
                  {"failures", failures},
                  {"type_accuracy", n ? static_cast<double>(typeOk) / n : 0.0},
                  {"attribute_accuracy", attrN ? static_cast<double>(attrOk) / attrN : 1.0},
                  {"ms_per_case", n - failures > 0 ? totalMs / (n - failures) : 0.0}};
  for (const auto& [k, s] : errors)
    summary["measurements"][k] = s.toJson();
  for (const auto& [m, st] : methodStats)
    summary["classifiers"][m] = {{"type_accuracy", n ? static_cast<double>(st.first) / n : 0.0},
                                 {"ms_per_case", n ? st.second / n : 0.0}};
  std::cout << json({{"summary", summary}}).dump(2) << "\n";
  if (!outDir.empty())
    drafts::writeJsonFile(outDir / "eval.json", {{"summary", summary}, {"cases", cases}});
  return failures == 0 ? 0 : 1;
}

}  // namespace

void addPipelineCommands(CLI::App& app) {
  auto* cap = app.add_subcommand("capture", "Run GarmCap on a bare-form and a dressed frame");
  static fs::path empty, dressed, calibration, out;
  cap->add_option("--empty", empty, "bare-form frame (PNG/JPEG)")->required();
  cap->add_option("--dressed", dressed, "dressed frame, same camera and size")->required();
  cap->add_option("--calibration", calibration, "calibration JSON (garmcap calibrate)")->required();
  cap->add_option("--out", out, "output folder")->required();
  cap->callback([] {
    const cv::Mat e = readImage(empty, "bare-form frame");
    const cv::Mat d = readImage(dressed, "dressed frame");
    const json cal = drafts::readJsonFile(calibration);
    const auto r = pipeline::runCapture(e, d, cal);
    writeCaptureOutputs(out, r);
    std::cout << r.toJson().dump(2) << "\n";
  });

  CLI::App* rig = nullptr;
  for (auto* sub : app.get_subcommands([](CLI::App* a) { return a->get_name() == "rig"; }))
    rig = sub;
  if (rig == nullptr) {
    rig = app.add_subcommand("rig", "Rigs of replayed images: make (simulator), eval (pipeline)");
    rig->require_subcommand(1);
  }
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
  static fs::path refsOut;
  eval->add_option("--dump-references", refsOut,
                   "write the type database's silhouettes of the first case here");
  eval->callback([] {
    if (!refsOut.empty()) {
      const auto rig = capture::readRig(rigDir);
      const auto c = capture::loadRigCase(rig.cases.front().dir);
      const auto ctx = pipeline::buildCaptureContext(c.calibration);
      fs::create_directories(refsOut);
      const auto refs = pipeline::renderReferenceSilhouettes(*ctx->view, ctx->body, nullptr);
      for (std::size_t i = 0; i < refs.size(); ++i) {
        std::string name = std::to_string(i) + "_" + refs[i].type;
        for (const auto& [k, v] : refs[i].attributes)
          name += "_" + v;
        writeImage(refsOut / (name + ".png"), refs[i].mask);
      }
      for (const auto& n : ctx->notes)
        std::cerr << n << "\n";
    }
    const int rc = rigEval(rigDir, evalOut, compare, workMp);
    if (rc != 0)
      throw std::runtime_error("some rig cases failed (see their \"error\")");
  });
}

}  // namespace garmcap::cli
