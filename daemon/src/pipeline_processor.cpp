// The production CaptureProcessor: calib/ for the bare-form frame, core/garmcap's runCapture for
// the dressed frame, core/dsw for the size run.

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <future>
#include <mutex>
#include <opencv2/imgproc.hpp>
#include <opencv2/objdetect.hpp>
#include <stdexcept>

#include "garmcap/calib/registration.h"
#include "garmcap/daemon/capture_processor.h"
#include "garmcap/daemon/config.h"
#include "garmcap/daemon/garment_colour.h"
#include "garmcap/daemon/stage_progress.h"
#include "garmcap/drafts/panel_measure.h"
#include "garmcap/drafts/pattern_io.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/dsw/grading.h"
#include "garmcap/dsw/size_guide.h"
#include "garmcap/dsw/size_run.h"
#include "garmcap/pipeline/capture_context.h"
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
    options_.productShadow = config.productShadow;
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
    nlohmann::json calibration = nlohmann::json::parse(calib::calibrationToJson(c));
    // The per-calibration context (the form seen in this pose, the classifier's references:
    // about 1 s) and the bare frame ready for comparison are prepared now, while staff dress the
    // form, not on the first garment's capture. A calibration the pipeline cannot use fails here,
    // with the reason, instead of every capture.
    progress("preparing the pipeline", 0.95);
    auto prepared = std::make_shared<const pipeline::PreparedCapture>(
        pipeline::buildCaptureContext(calibration, sizeChart_), emptyBgr, options_.workMegapixels);
    warmUp(*prepared, emptyBgr);
    std::lock_guard lock(preparedMutex_);
    prepared_ = std::move(prepared);
    preparedFor_ = calibration;
    return calibration;
  }

  ProcessedCapture process(const cv::Mat& emptyBgr, const cv::Mat& dressedBgr,
                           const nlohmann::json& calibration, const ProgressFn& progress,
                           std::shared_ptr<const pipeline::CorrectionTable> corrections) override {
    // The pipeline runs from 5 % to 80 % of this call; each stage's end moves the bar by the
    // share of time that stage takes on this station, and names the stage that runs next.
    constexpr double kPipelineFrom = 0.05, kPipelineTo = 0.8;
    progress("context", kPipelineFrom);
    pipeline::CaptureOptions options = options_;
    options.corrections = std::move(corrections);
    double doneShare = 0;
    options.onStageDone = [&](const pipeline::StageTiming& t) {
      const StageProgress::Step step = stageProgress_.after(t.stage);
      doneShare = std::max(doneShare, step.fraction);
      progress(step.next.empty() ? t.stage : step.next,
               kPipelineFrom + (kPipelineTo - kPipelineFrom) * doneShare);
    };
    const auto t0 = std::chrono::steady_clock::now();
    pipeline::CaptureResult r =
        pipeline::runCapture(*prepared(emptyBgr, calibration), dressedBgr, options);
    spdlog::info(
        "pipeline: runCapture took {} ms",
        std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0)
            .count());
    std::vector<std::pair<std::string, double>> stageMs;
    for (const auto& t : r.timings)
      stageMs.emplace_back(t.stage, t.ms);
    stageProgress_.learn(stageMs);
    progress("grading sizes", kPipelineTo);
    ProcessedCapture out;
    out.type = r.type;
    out.attributes = r.attributes;
    out.confidence = r.confidence;
    out.warnings = r.warnings;
    out.measurementsCm = r.measurements;
    // The CLI's result.json (CaptureResult::toJson), so both tell the same story in one shape;
    // the colours are added by nameColours below.
    out.result = r.toJson();
    storeBasePattern(out, drafts::patternToJsonValue(r.pattern));
    auto addImage = [&](const char* kind, const cv::Mat& m) {
      if (!m.empty())
        out.images[kind] = m;
    };
    addImage("cutout", r.cutout);
    addImage("product", r.product);
    addImage("product_4x5", r.productPortrait);
    addImage("silhouette", r.silhouette);
    addImage("overlay", r.overlay);
    addImage("texture", r.texture);
    // The photos' encodings (about half a second on 2 cores at 12 MP) start now, beside the
    // colours and the size run, which are single-threaded: the same bytes as encoded after them.
    out.encodedImages = std::async(std::launch::async, [images = out.images] {
                          return pipeline::encodeImageSet({images.begin(), images.end()});
                        }).share();
    nameColours(dressedBgr, r, out);
    grade(r, out, progress);
    return out;
  }

  ProcessedCapture processBack(const cv::Mat& emptyBgr, const cv::Mat& dressedBgr,
                               const cv::Mat& backBgr, const nlohmann::json& calibration,
                               const ProgressFn& progress) override {
    progress("context", 0.05);
    // Only the photos are wanted: the front's measurements and pattern stay as filed, so the
    // texture and grading are not redone. The front's own photos are made all the same (the
    // ghost composite is drawn on them) and dropped here.
    pipeline::CaptureOptions options = options_;
    options.makeTexture = false;
    options.makeProductImages = true;
    options.backFrame = backBgr;
    options.onStageDone = [&](const pipeline::StageTiming& t) { progress(t.stage, 0.5); };
    const auto t0 = std::chrono::steady_clock::now();
    pipeline::CaptureResult r =
        pipeline::runCapture(*prepared(emptyBgr, calibration), dressedBgr, options);
    spdlog::info(
        "pipeline: runCapture with the back shot took {} ms",
        std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0)
            .count());
    ProcessedCapture out;
    const std::pair<const char*, const cv::Mat&> images[] = {
        {"cutout_back", r.backCutout},
        {"product_back", r.backProduct},
        {"product_back_4x5", r.backProductPortrait},
        {"product_ghost", r.ghostProduct},
        {"product_ghost_4x5", r.ghostProductPortrait}};
    for (const auto& [kind, image] : images)
      if (!image.empty())
        out.images[kind] = image;
    if (out.images.empty())
      throw std::runtime_error("the back shot gave no photo (" + nlohmann::json(r.warnings).dump() +
                               ")");
    out.result = {{"back_shot", r.backShot}};
    // The front's warnings were given when the item was filed; only the back shot's are new
    // (stage_back_shot.cpp words each of them with "back shot" or "ghost-mannequin").
    for (const auto& w : r.warnings)
      if (w.find("back shot") != std::string::npos ||
          w.find("ghost-mannequin") != std::string::npos)
        out.warnings.push_back(w);
    return out;
  }

 private:
  // The preparation made at calibration, or, for a calibration made before this process started
  // (or replaced since), one made now and kept for the captures that follow. The station hands
  // each calibration's own bare frame with it, so the calibration identifies the pair.
  std::shared_ptr<const pipeline::PreparedCapture> prepared(const cv::Mat& emptyBgr,
                                                            const nlohmann::json& calibration) {
    std::lock_guard lock(preparedMutex_);
    if (prepared_ && preparedFor_ == calibration)
      return prepared_;
    spdlog::info(
        "pipeline: preparing a calibration not prepared by this process (made before "
        "it started)");
    std::shared_ptr<const pipeline::CaptureContext> context;
    try {
      context = pipeline::buildCaptureContext(calibration, sizeChart_);
    } catch (const std::exception& e) {
      throw pipeline::CaptureError(pipeline::CaptureError::Reason::kBadInput,
                                   std::string("calibration: ") + e.what());
    }
    prepared_ = std::make_shared<const pipeline::PreparedCapture>(std::move(context), emptyBgr,
                                                                  options_.workMegapixels);
    preparedFor_ = calibration;
    return prepared_;
  }

  // The first capture after a calibration took 0.25 s longer than the later ones at 12 MP, in
  // registration and the masks: their frame-sized buffers were first touched then (the heap
  // grows and its pages fault in; later captures reuse them, keepFrameMemoryMapped). The bare
  // frame run through the pipeline as if dressed touches them now, while staff dress the form;
  // it ends where the pipeline finds no garment, which is the expected answer and not logged.
  static void warmUp(const pipeline::PreparedCapture& prepared, const cv::Mat& emptyBgr) {
    pipeline::CaptureOptions o;
    o.makeProductImages = false;
    o.makeTexture = false;
    try {
      (void)pipeline::runCapture(prepared, emptyBgr, o);
    } catch (const pipeline::CaptureError& e) {
      if (e.reason() != pipeline::CaptureError::Reason::kNoGarment)
        spdlog::warn("pipeline: warming up on the bare frame: {}", e.what());
    } catch (const std::exception& e) {
      // Only the first capture's speed depends on it: the calibration stands.
      spdlog::warn("pipeline: warming up on the bare frame failed: {}", e.what());
    }
  }

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

  // The colours a shop lists: from the cut-out's opaque pixels (the garment alone), else from
  // the frame under the silhouette. A garment too small to name is a warning, not a failure.
  static void nameColours(const cv::Mat& dressedBgr, const pipeline::CaptureResult& r,
                          ProcessedCapture& out) {
    GarmentColours colours;
    try {
      auto named = captureColours(r, dressedBgr);
      if (!named)
        return;
      colours = std::move(*named);
    } catch (const std::exception& e) {
      out.warnings.push_back(std::string("colour not named: ") + e.what());
      return;
    }
    nlohmann::json list = nlohmann::json::array();
    for (const auto& c : colours.colours) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "#%02x%02x%02x", c.meanBgr[2], c.meanBgr[1], c.meanBgr[0]);
      list.push_back(
          {{"name", c.name}, {"share", std::round(c.share * 1000) / 1000}, {"rgb", hex}});
    }
    out.result["colors"] = list;
    out.result["pattern"] = colours.printed ? "print" : "solid";
    if (!colours.colours.empty())
      out.attributes["color"] = colours.label();
    out.attributes["pattern"] = colours.printed ? "print" : "solid";
    // The texture stage ("fabric") finds straight repeats (stripes, checks) and calls anything
    // else solid; a print it cannot straighten is still a print, so the item says one thing.
    if (const auto f = out.attributes.find("fabric");
        colours.printed && f != out.attributes.end() && f->second == "solid")
      f->second = "print";
    out.result["attributes"] = out.attributes;
  }

  // The size run: the measured pattern graded by DSW to every body of the configured chart, and
  // the shopper's size guide (core/dsw). The item's size (the sample size of the graded files)
  // is the chart size of the body the pattern was drafted for (the form's, dsw::sampleSizeOf),
  // not the garment's own circumference nor the garment less a default ease (a design's ease
  // is its own). A size that cannot be graded is left out with a warning naming it; nothing is
  // made up.
  void grade(const pipeline::CaptureResult& r, ProcessedCapture& out, const ProgressFn& progress) {
    if (r.pattern.panels.empty())
      return;  // runCapture has said why there is no pattern
    const drafts::SizeChart* chart = nullptr;
    try {
      chart = &drafts::sizeChart(sizeChart_);
    } catch (const std::exception& e) {
      out.warnings.push_back(std::string("size run not graded: ") + e.what());
      return;
    }
    auto nearest = dsw::sampleSizeOf(r.pattern, *chart);
    if (!nearest) {  // a draft without its body's girths: the garment less the recipe's ease
      const auto body = dsw::bodyFittedBy(r.pattern.type, r.measurements);
      nearest = body ? dsw::nearestChartSize(*chart, *body) : std::nullopt;
    }
    if (!nearest) {
      out.warnings.push_back("no size guide: the garment has no bust, waist or hip to size it by");
      return;
    }
    out.baseSize = chart->sizes[*nearest];
    progress("grading sizes", 0.85);
    auto run = dsw::gradeSizeRun(r.pattern, *chart, dsw::GradeOptions{},
                                 dsw::SizeRunPolicy::skipUngradable);
    std::optional<dsw::SizeGuide> guide;
    if (!run) {
      out.warnings.push_back("size run not graded: " + run.error().message);
    } else {
      for (const auto& why : run->skipped)
        out.warnings.push_back("size run: " + why);
      for (std::size_t i = 0; i < run->sizes.size(); ++i)
        out.patterns[run->sizes[i]] = drafts::patternToJsonValue(run->patterns[i]);
      const auto at = std::find(run->sizes.begin(), run->sizes.end(), out.baseSize);
      if (at != run->sizes.end()) {
        auto built = dsw::buildSizeGuide(*run, *chart, r.type, r.measurements,
                                         static_cast<std::size_t>(at - run->sizes.begin()));
        if (built)
          guide = std::move(built).value();
        else
          out.warnings.push_back("no size guide: " + built.error().message);
      }
    }
    if (!guide)  // the item's own size alone, so shoppers still see what was measured
      guide = dsw::singleSizeGuide(r.type, chart->name, out.baseSize, r.measurements);
    if (!guide->measurements.empty())
      out.sizeGuide = nlohmann::json::parse(dsw::sizeGuideJson(*guide));
  }

  pipeline::CaptureOptions options_;
  StageProgress stageProgress_;
  std::string sizeChart_;
  std::string formPath_;
  std::mutex formMutex_;
  std::unique_ptr<calib::FormModel> form_;
  std::mutex preparedMutex_;
  std::shared_ptr<const pipeline::PreparedCapture> prepared_;
  nlohmann::json preparedFor_;  // the calibration prepared_ was made for
};

}  // namespace

ProcessedCapture CaptureProcessor::processBack(const cv::Mat&, const cv::Mat&, const cv::Mat&,
                                               const nlohmann::json&, const ProgressFn&) {
  throw std::runtime_error("this station's processor cannot make back photos");
}

std::unique_ptr<CaptureProcessor> makePipelineProcessor(const Config& config) {
  return std::make_unique<PipelineProcessor>(config);
}

// What zbar scans: the still in grey, cropped to what is not bare green screen and with the
// screen left inside the crop made flat (each 8 px block its mean grey). zbar spends most of its
// time on the screen's sensor noise (every noise edge feeds its decoders): on the rig's 12 MP
// still, 0.4 s of CPU on the whole frame against about 0.15 s on this. The garment, the form and
// anything hung on them, the tag included, keep every pixel and every scan line. A block is screen
// only when it is both green (as the chroma key means it) and smooth; a tag is paper with ink,
// never smooth, so even a tag printed on green is kept. Kept blocks grow by a margin so that the
// tag's edge and quiet zone, which share blocks with the screen, are not flattened; the crop
// reaches a little beyond, so that a quiet zone ends in an edge (zbar does not read a symbol whose
// quiet zone runs into the end of its scan line), and is never smaller than zbar's QR binarisation
// needs (below).
cv::Mat hangTagScanImage(const cv::Mat& bgr, cv::Rect* region, const cv::Mat& bare) {
  if (region)
    *region = cv::Rect();
  if (bgr.empty())
    return {};
  cv::Mat gray;
  if (bgr.channels() == 1)
    gray = bgr;
  else
    cv::cvtColor(bgr, gray, bgr.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
  if (region)
    *region = cv::Rect(0, 0, gray.cols, gray.rows);
  constexpr int kBlock = 8;     // px a side
  constexpr int kMargin = 4;    // blocks kept around what is not screen (32 px)
  constexpr int kBeyond = 2;    // blocks of flat screen the crop keeps around those (16 px)
  constexpr int kSmooth = 16;   // mean |dx| + |dy| of a screen block; the rig's noise gives 6-8
  constexpr int kGreener = 30;  // G over max(B, R), and G at least 1.5 times it, like the key
  const cv::Size blocks(gray.cols / kBlock, gray.rows / kBlock);
  if (bgr.channels() < 3 || blocks.width <= 2 * (kMargin + kBeyond) ||
      blocks.height <= 2 * (kMargin + kBeyond))
    return gray;  // a small or grey frame: scanned whole, as it costs little
  const cv::Rect tiled(0, 0, blocks.width * kBlock, blocks.height * kBlock);
  cv::Mat colour;
  cv::resize(bgr(tiled), colour, blocks, 0, 0, cv::INTER_AREA);
  // Texture per block: the mean absolute difference to the right and the lower neighbour, on
  // every other row, one band of blocks at a time (buffers that stay in cache).
  cv::Mat1b texture(blocks);
  {
    cv::Mat dx, dy, sum, band;
    const int w = tiled.width - 1;
    for (int by = 0; by < blocks.height; ++by) {
      const int y0 = by * kBlock;
      // Rows y0, y0 + 2, ...: a header over every other row of the band.
      const cv::Mat rows(kBlock / 2, w, CV_8U, gray.ptr(y0), gray.step * 2);
      const cv::Mat right(kBlock / 2, w, CV_8U, gray.ptr(y0) + 1, gray.step * 2);
      const cv::Mat below(kBlock / 2, w, CV_8U, gray.ptr(y0 + 1), gray.step * 2);
      cv::absdiff(rows, right, dx);
      cv::absdiff(rows, below, dy);
      cv::add(dx, dy, sum);  // saturates at 255, far above kSmooth
      cv::resize(sum(cv::Rect(0, 0, (w / kBlock) * kBlock, kBlock / 2)), band,
                 cv::Size(w / kBlock, 1), 0, 0, cv::INTER_AREA);
      band.copyTo(texture.row(by).colRange(0, band.cols));
      // The last column has no right neighbour in the tiled part: it takes its neighbour's.
      texture.row(by)
          .colRange(band.cols, blocks.width)
          .setTo(band.at<unsigned char>(band.cols - 1));
    }
  }
  // With the calibration's bare-form frame: blocks whose mean colour is the bare frame's (within
  // kSame in every channel) show no garment and no tag either (ink on a tag moves the mean of a
  // block it covers far more). The form, its arms and legs then go too.
  cv::Mat bareColour;
  if (!bare.empty() && bare.size() == bgr.size() && bare.type() == bgr.type())
    cv::resize(bare(tiled), bareColour, blocks, 0, 0, cv::INTER_AREA);
  constexpr int kSame = 12;  // grey levels; sensor noise moves a block's mean by about 1
  cv::Mat1b flat(blocks, 0);
  const int ch = bgr.channels();
  for (int y = 0; y < blocks.height; ++y) {
    const auto* c = colour.ptr<unsigned char>(y);
    const auto* e = bareColour.empty() ? nullptr : bareColour.ptr<unsigned char>(y);
    const auto* t = texture.ptr<unsigned char>(y);
    auto* out = flat.ptr<unsigned char>(y);
    for (int x = 0; x < blocks.width; ++x) {
      const int b = c[x * ch], g = c[x * ch + 1], r = c[x * ch + 2];
      const int m = std::max(b, r);
      const bool screen = g - m >= kGreener && 2 * g >= 3 * m && t[x] < kSmooth;
      const bool unchanged = e && std::abs(b - e[x * ch]) < kSame &&
                             std::abs(g - e[x * ch + 1]) < kSame &&
                             std::abs(r - e[x * ch + 2]) < kSame;
      out[x] = screen || unchanged ? 255 : 0;
    }
  }
  cv::Mat1b keep = 255 - flat;
  cv::dilate(keep, keep,
             cv::getStructuringElement(cv::MORPH_RECT, {2 * kMargin + 1, 2 * kMargin + 1}));
  cv::Rect box = cv::boundingRect(keep);
  if (box.empty()) {
    if (region)
      *region = cv::Rect();
    return {};  // bare screen only: no tag
  }
  box = cv::Rect(box.tl() - cv::Point(kBeyond, kBeyond),
                 box.size() + cv::Size(2 * kBeyond, 2 * kBeyond));
  // zbar binarises a QR code with a window that grows with the scanned image up to 256 px, which
  // it reaches at about 1040 px: a smaller crop would read small QR modules differently from the
  // whole frame (in the tests, 3 px per module instead of 2). So the crop is at least that wide
  // and high, or the whole frame, grown about its centre.
  constexpr int kMinCropBlocks = 1048 / kBlock;
  const auto grow = [](int& at, int& len, int want, int limit) {
    want = std::min(want, limit);
    if (len >= want)
      return;
    at = std::clamp(at - (want - len) / 2, 0, limit - want);
    len = want;
  };
  grow(box.x, box.width, kMinCropBlocks, blocks.width);
  grow(box.y, box.height, kMinCropBlocks, blocks.height);
  box &= cv::Rect(0, 0, blocks.width, blocks.height);
  // Blocks to pixels; a crop reaching the last block takes the frame's leftover pixels too.
  cv::Rect crop(box.x * kBlock, box.y * kBlock, box.width * kBlock, box.height * kBlock);
  if (box.br().x == blocks.width)
    crop.width = gray.cols - crop.x;
  if (box.br().y == blocks.height)
    crop.height = gray.rows - crop.y;
  if (region)
    *region = crop;
  cv::Mat out = gray(crop).clone();  // zbar reads one contiguous buffer
  // Each left-out block becomes its own mean grey: no noise edges for zbar, and no edge where
  // there was none (a light form next to a tag stays light, the screen mid-grey).
  cv::Mat blockGray;
  cv::resize(gray(tiled), blockGray, blocks, 0, 0, cv::INTER_AREA);
  for (int by = 0; by < box.height; ++by) {
    const auto* k = keep.ptr<unsigned char>(box.y + by) + box.x;
    const auto* v = blockGray.ptr<unsigned char>(box.y + by) + box.x;
    for (int row = 0; row < kBlock; ++row) {
      auto* px = out.ptr<unsigned char>(by * kBlock + row);
      for (int bx = 0; bx < box.width; ++bx)
        if (!k[bx])
          std::memset(px + bx * kBlock, v[bx], kBlock);
    }
  }
  return out;
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
std::string decodeWithZbar(const cv::Mat& gray) {
  using namespace zbar;  // zbar.h puts its C API in namespace zbar when compiled as C++
  if (gray.empty())
    return "";
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

std::string decodeHangTagSku(const cv::Mat& bgr, const cv::Mat& bare) {
  if (bgr.empty())
    return "";
#ifdef GARMCAP_HAVE_ZBAR
  try {
    return decodeWithZbar(hangTagScanImage(bgr, nullptr, bare));
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

std::string decodeSkuInGrey(const cv::Mat& grey) {
#ifdef GARMCAP_HAVE_ZBAR
  if (grey.type() != CV_8UC1)
    throw std::invalid_argument("decodeSkuInGrey: the image is not 8-bit grey");
  return decodeWithZbar(grey.isContinuous() ? grey : grey.clone());
#else
  (void)grey;
  return "";
#endif
}

bool patternIsEmpty(const nlohmann::json& pattern) {
  const auto panels = pattern.find("panels");
  return !pattern.is_object() || panels == pattern.end() || !panels->is_array() || panels->empty();
}

void storeBasePattern(ProcessedCapture& out, const nlohmann::json& pattern) {
  if (!patternIsEmpty(pattern)) {
    out.patterns["base"] = pattern;
    return;
  }
  out.patterns.erase("base");
  const bool said = std::any_of(out.warnings.begin(), out.warnings.end(),
                                [](const auto& w) { return w.rfind(kNoPatternWarning, 0) == 0; });
  if (!said)
    out.warnings.push_back(std::string(kNoPatternWarning) + "the draft has no pieces");
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
