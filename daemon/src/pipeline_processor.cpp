// The production CaptureProcessor: calib/ for the bare-form frame, core/garmcap's runCapture for
// the dressed frame, core/dsw for the size run.

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <opencv2/objdetect.hpp>

#include "garmcap/calib/registration.h"
#include "garmcap/daemon/capture_processor.h"
#include "garmcap/daemon/config.h"
#include "garmcap/drafts/panel_measure.h"
#include "garmcap/drafts/pattern_io.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/dsw/grading.h"
#include "garmcap/pipeline/capture_pipeline.h"

#ifdef GARMCAP_HAVE_ZBAR
#include <zbar.h>
#endif

namespace garmcap::daemon {

namespace {

class PipelineProcessor : public CaptureProcessor {
 public:
  explicit PipelineProcessor(const Config& config) {
    options_.makeProductImages = config.makeProductImages;
    options_.makeTexture = config.makeTexture;
    options_.productSizePx = config.productSizePx;
    sizeChart_ = config.sizeChart;
    formPath_ = config.formPath;
  }

  nlohmann::json calibrate(const cv::Mat& emptyBgr, const ProgressFn& progress) override {
    if (emptyBgr.empty() || emptyBgr.type() != CV_8UC3)
      throw std::runtime_error("calibration failed: the bare-form frame is not an 8-bit BGR image");
    progress("form model", 0.05);
    const calib::FormModel& model = form();
    progress("registration", 0.2);
    const calib::Registration reg =
        calib::registerForm(model, cv::Mat3b(emptyBgr), "bare-form frame");
    progress("calibration", 0.9);
    const calib::Calibration c =
        calib::makeCalibration(model, reg, formPath_, "empty.png", std::nullopt);
    spdlog::info("calibration: IoU {:.3f} after {} iterations", reg.iou, reg.iterations);
    return nlohmann::json::parse(calib::calibrationToJson(c));
  }

  ProcessedCapture process(const cv::Mat& emptyBgr, const cv::Mat& dressedBgr,
                           const nlohmann::json& calibration, const ProgressFn& progress) override {
    progress("garmcap", 0.05);
    const auto t0 = std::chrono::steady_clock::now();
    pipeline::CaptureResult r = pipeline::runCapture(emptyBgr, dressedBgr, calibration, options_);
    spdlog::info(
        "pipeline: runCapture took {} ms",
        std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0)
            .count());
    progress("garmcap", 0.8);
    ProcessedCapture out;
    out.type = r.type;
    out.attributes = r.attributes;
    out.confidence = r.confidence;
    out.warnings = r.warnings;
    out.measurementsCm = r.measurements;
    out.result = {
        {"type", r.type},          {"attributes", r.attributes},     {"confidence", r.confidence},
        {"runner_up", r.runnerUp}, {"measurements", r.measurements}, {"warnings", r.warnings}};
    nlohmann::json timings = nlohmann::json::array();
    for (const auto& t : r.timings)
      timings.push_back({{"stage", t.stage}, {"ms", t.ms}});
    out.result["timings"] = timings;
    out.patterns["base"] = drafts::patternToJsonValue(r.pattern);
    auto addImage = [&](const char* kind, const cv::Mat& m) {
      if (!m.empty())
        out.images[kind] = m;
    };
    addImage("cutout", r.cutout);
    addImage("product", r.product);
    addImage("silhouette", r.silhouette);
    addImage("overlay", r.overlay);
    addImage("texture", r.texture);
    grade(r, out, progress);
    progress("grading", 0.95);
    return out;
  }

 private:
  const calib::FormModel& form() {
    std::lock_guard lock(formMutex_);
    if (!form_) {
      if (formPath_.empty())
        throw std::runtime_error(
            "calibration failed: no dress-form model configured ([camera] form / --form)");
      form_ = std::make_unique<calib::FormModel>(calib::FormModel::load(formPath_));
    }
    return *form_;
  }

  // The size run: the measured pattern graded by DSW to every body of the configured chart, and
  // a size guide of the graded garments' own measurements. A size that cannot be graded is
  // left out with a warning naming it; nothing is made up.
  void grade(const pipeline::CaptureResult& r, ProcessedCapture& out, const ProgressFn& progress) {
    const drafts::SizeChart* chart = nullptr;
    try {
      chart = &drafts::sizeChart(sizeChart_);
    } catch (const std::exception& e) {
      out.warnings.push_back(std::string("size run not graded: ") + e.what());
      return;
    }
    // The base size: the chart body nearest to the measured one on the names both carry.
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < chart->sizes.size(); ++i) {
      double d2 = 0;
      int n = 0;
      for (const auto& [name, cm] : r.measurements)
        if (chart->bodies[i].has(name)) {
          const double d = chart->bodies[i].values().at(name) - cm;
          d2 += d * d;
          ++n;
        }
      if (n > 0 && d2 / n < best) {
        best = d2 / n;
        out.baseSize = chart->sizes[i];
      }
    }
    nlohmann::json guide{{"chart", chart->name}, {"units", "cm"}, {"base_size", out.baseSize}};
    nlohmann::json sizes = nlohmann::json::array();
    nlohmann::json table = nlohmann::json::object();
    for (std::size_t i = 0; i < chart->sizes.size(); ++i) {
      const std::string& size = chart->sizes[i];
      progress("grading " + size,
               0.8 + 0.15 * static_cast<double>(i) / static_cast<double>(chart->sizes.size()));
      auto graded = dsw::gradePattern(r.pattern, chart->bodies[i], dsw::GradeOptions{});
      if (!graded.ok()) {
        out.warnings.push_back("size " + size + " not graded: " + graded.error().message);
        continue;
      }
      try {
        out.patterns[size] = drafts::patternToJsonValue(graded.value());
        for (const auto& [name, cm] : drafts::measurePattern(graded.value()))
          table[name][size] = cm;
        sizes.push_back(size);
      } catch (const std::exception& e) {
        out.warnings.push_back("size " + size + " not measured: " + e.what());
      }
    }
    if (sizes.empty())
      return;
    guide["sizes"] = sizes;
    guide["measurements"] = table;
    out.sizeGuide = guide;
  }

  pipeline::CaptureOptions options_;
  std::string sizeChart_;
  std::string formPath_;
  std::mutex formMutex_;
  std::unique_ptr<calib::FormModel> form_;
};

}  // namespace

std::unique_ptr<CaptureProcessor> makePipelineProcessor(const Config& config) {
  return std::make_unique<PipelineProcessor>(config);
}

namespace {

bool isSkuText(const std::string& text) {
  if (text.empty() || text.size() > 64)
    return false;
  return std::all_of(text.begin(), text.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-';
  });
}

#ifdef GARMCAP_HAVE_ZBAR
// zbar reads QR codes and the 1-D codes of retail and in-house labels. Symbologies prone to
// false reads in a busy frame (Interleaved 2 of 5, Codabar, DataBar) stay off.
std::string decodeWithZbar(const cv::Mat& bgr) {
  using namespace zbar;  // zbar.h puts its C API in namespace zbar when compiled as C++
  cv::Mat gray;
  cv::cvtColor(bgr, gray, bgr.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
  std::unique_ptr<zbar_image_scanner_t, void (*)(zbar_image_scanner_t*)> scanner(
      zbar_image_scanner_create(), zbar_image_scanner_destroy);
  std::unique_ptr<zbar_image_t, void (*)(zbar_image_t*)> image(zbar_image_create(),
                                                               zbar_image_destroy);
  if (!scanner || !image)
    throw std::runtime_error("zbar: cannot allocate a scanner");
  zbar_image_scanner_set_config(scanner.get(), ZBAR_NONE, ZBAR_CFG_ENABLE, 0);
  for (zbar_symbol_type_t t :
       {ZBAR_QRCODE, ZBAR_EAN13, ZBAR_EAN8, ZBAR_UPCA, ZBAR_UPCE, ZBAR_CODE128, ZBAR_CODE39})
    zbar_image_scanner_set_config(scanner.get(), t, ZBAR_CFG_ENABLE, 1);
  zbar_image_set_format(image.get(), zbar_fourcc('Y', '8', '0', '0'));
  zbar_image_set_size(image.get(), static_cast<unsigned>(gray.cols),
                      static_cast<unsigned>(gray.rows));
  zbar_image_set_data(image.get(), gray.data, gray.total(), nullptr);  // borrowed, not freed
  if (zbar_scan_image(scanner.get(), image.get()) <= 0)
    return "";
  // QR first: a tag carrying both prints the SKU in the QR and a retail code in the bars.
  std::string best;
  for (const zbar_symbol_t* sym = zbar_image_first_symbol(image.get()); sym;
       sym = zbar_symbol_next(sym)) {
    const std::string text = zbar_symbol_get_data(sym);
    if (!isSkuText(text))
      continue;
    if (zbar_symbol_get_type(sym) == ZBAR_QRCODE)
      return text;
    if (best.empty())
      best = text;
  }
  return best;
}
#endif

}  // namespace

std::string hangTagDecoder() {
#ifdef GARMCAP_HAVE_ZBAR
  return "zbar";
#else
  return "opencv";
#endif
}

std::string decodeHangTagSku(const cv::Mat& bgr) {
  if (bgr.empty())
    return "";
#ifdef GARMCAP_HAVE_ZBAR
  try {
    return decodeWithZbar(bgr);
  } catch (const std::exception& e) {
    spdlog::warn("sku: reading the hang tag failed: {}", e.what());
    return "";
  }
#else
  try {
    cv::QRCodeDetector detector;
    std::vector<cv::Point> corners;
    const std::string text = detector.detectAndDecode(bgr, corners);
    return isSkuText(text) ? text : "";
  } catch (const cv::Exception& e) {
    spdlog::warn("sku: QR detection failed: {}", e.what());
    return "";
  }
#endif
}

std::string expandNamingTemplate(const std::string& pattern,
                                 const std::map<std::string, std::string>& values) {
  std::string out;
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] == '{') {
      const std::size_t close = pattern.find('}', i);
      if (close != std::string::npos) {
        auto it = values.find(pattern.substr(i + 1, close - i - 1));
        if (it != values.end()) {
          out += it->second;
          i = close;
          continue;
        }
      }
    }
    out.push_back(pattern[i]);
  }
  for (char& c : out)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-'))
      c = '_';
  while (!out.empty() && out.front() == '.')
    out.erase(out.begin());
  if (out.empty())
    out = "item";
  return out;
}

}  // namespace garmcap::daemon
