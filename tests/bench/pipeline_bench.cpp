// GarmCap speed and memory at camera resolutions, and the coarse-to-fine GrabCut against plain
// full-resolution GrabCut on the same trimap.
//
//   build/bin/pipeline_bench [--sizes 480x640,1728x2304,3000x4000] [--reps 3] [--full-grabcut]
//                            [--default-malloc] [--work-mp MP] [--no-compare]
//
// Like garmcapd it keeps freed frame memory mapped (pipeline::keepFrameMemoryMapped);
// --default-malloc leaves glibc's defaults, to measure what that saves.
// For each size (ascending) a simulated dress scene is rendered on the bundled dress form, the
// pipeline runs once to build its per-calibration context (reported apart: the daemon builds it
// once per calibration), then `reps` times; the table gives the median wall time per stage and
// the process's peak resident memory after that size (sizes run ascending, so the peak belongs
// to the largest size so far). The GrabCut comparison cuts the same trimap (sure garment = true
// coverage eroded by 1 cm, sure background beyond 1 cm outside it, probable in between) both
// ways and reports time, the ratio and each mask's IoU with the true coverage. Plain GrabCut
// at 12 MP takes minutes on 2 cores, so it runs only with --full-grabcut above 4 MP; --no-compare
// leaves the comparison out. --work-mp sets the pipeline's work-frame size (CaptureOptions).
// Numbers are wall-clock: compare ratios from one run, not absolute times between machines.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "garmcap/calib/form_model.h"
#include "garmcap/pipeline/capture_pipeline.h"
#include "garmcap/pipeline/grabcut_refine.h"
#include "garmcap/sim/scene.h"
#include "garmcap/sim/sim.h"

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double peakRssMb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

std::vector<cv::Size> parseSizes(const std::string& arg) {
  std::vector<cv::Size> out;
  std::stringstream ss(arg);
  std::string item;
  while (std::getline(ss, item, ',')) {
    int w = 0, h = 0;
    if (std::sscanf(item.c_str(), "%dx%d", &w, &h) != 2 || w < 64 || h < 64)
      throw std::invalid_argument("--sizes: '" + item + "' is not WIDTHxHEIGHT");
    out.emplace_back(w, h);
  }
  std::sort(out.begin(), out.end(), [](cv::Size a, cv::Size b) { return a.area() < b.area(); });
  return out;
}

cv::Mat trimapFromCoverage(const cv::Mat1f& coverage, double pxPerCm) {
  const cv::Mat fg = coverage > 0.5f;
  const int r = std::max(2, static_cast<int>(std::lround(pxPerCm)));
  const cv::Mat k = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1));
  cv::Mat sure, near;
  cv::erode(fg, sure, k);
  cv::dilate(fg, near, k);
  cv::Mat trimap(fg.size(), CV_8UC1, cv::Scalar(cv::GC_BGD + 0));
  trimap.setTo(cv::GC_PR_BGD + 0, near);
  trimap.setTo(cv::GC_PR_FGD + 0, fg);
  trimap.setTo(cv::GC_FGD + 0, sure);
  return trimap;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace garmcap;
  std::string sizesArg = "480x640,1728x2304,3000x4000";
  int reps = 3;
  bool fullGrabCut = false;
  bool systemAllocator = false;
  bool compare = true;
  pipeline::CaptureOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--sizes" && i + 1 < argc) {
      sizesArg = argv[++i];
    } else if (a == "--reps" && i + 1 < argc) {
      reps = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--full-grabcut") {
      fullGrabCut = true;
    } else if (a == "--default-malloc") {
      systemAllocator = true;
    } else if (a == "--no-compare") {
      compare = false;
    } else if (a == "--work-mp" && i + 1 < argc) {
      options.workMegapixels = std::atof(argv[++i]);
      if (!(options.workMegapixels > 0.05)) {
        std::fprintf(stderr, "pipeline_bench: --work-mp must be above 0.05 (megapixels)\n");
        return 2;
      }
    } else {
      std::fprintf(stderr,
                   "usage: pipeline_bench [--sizes WxH,...] [--reps N] [--full-grabcut] "
                   "[--default-malloc] [--work-mp MP] [--no-compare]\n");
      return 2;
    }
  }
  if (!systemAllocator)
    pipeline::keepFrameMemoryMapped();  // as garmcapd does
  try {
    const std::string formPath =
        std::string(GARMCAP_SHARED_DIR) + "/data/forms/garmentcode_mean_female/form.json";
    const calib::FormModel form = calib::FormModel::load(formPath);
    std::printf("%-10s %5s %8s %7s %7s %7s %7s %7s %7s %7s %7s %7s %8s %6s\n", "size", "MP",
                "context", "total", "regist", "masks", "grabcut", "type", "measure", "pattern",
                "images", "texture", "peak_MB", "class");
    struct GrabCutRow {
      cv::Size size;
      double c2fMs, fullMs, c2fIou, fullIou;
    };
    std::vector<GrabCutRow> grabRows;
    for (const cv::Size size : parseSizes(sizesArg)) {
      sim::RandomSceneOptions o;
      o.size = size;
      o.hardFraction = 0;
      o.type = "dress";
      const sim::SceneRenderer renderer(form, sim::randomScene(form, formPath, 11, o));
      const cv::Mat empty = renderer.renderEmpty(), dressed = renderer.renderDressed();
      const nlohmann::json cal = renderer.calibration();

      // The per-calibration context and the bare frame's preparation, made once as a station
      // makes them at its bare-form capture.
      auto t0 = Clock::now();
      const pipeline::PreparedCapture prepared(
          pipeline::buildCaptureContext(cal, pipeline::kDefaultSizeChart), empty,
          options.workMegapixels);
      const double contextMs = msSince(t0);
      pipeline::CaptureResult first = pipeline::runCapture(prepared, dressed, options);
      std::map<std::string, std::vector<double>> stages;
      for (int r = 0; r < reps; ++r) {
        t0 = Clock::now();
        const pipeline::CaptureResult res = pipeline::runCapture(prepared, dressed, options);
        stages["total"].push_back(msSince(t0));
        for (const auto& t : res.timings)
          stages[t.stage].push_back(t.ms);
      }
      std::printf(
          "%4dx%-5d %5.1f %8.0f %7.0f %7.0f %7.0f %7.0f %7.0f %7.0f %7.0f %7.0f %7.0f %8.0f %6s\n",
          size.width, size.height, static_cast<double>(size.area()) / 1e6, contextMs,
          median(stages["total"]), median(stages["registration"]), median(stages["masks"]),
          median(stages["grabcut"]), median(stages["type"]), median(stages["measure"]),
          median(stages["pattern"]), median(stages["images"]), median(stages["texture"]),
          peakRssMb(), first.type.c_str());

      if (!compare)
        continue;
      const cv::Mat1f truth = renderer.garmentCoverage();
      const cv::Mat truthMask = truth > 0.5f;
      const cv::Mat trimap = trimapFromCoverage(truth, cal["pose"]["px_per_cm"].get<double>());
      GrabCutRow row{size, 0, -1, 0, 0};
      t0 = Clock::now();
      const cv::Mat c2f = pipeline::grabCutCoarseToFine(dressed, trimap);
      row.c2fMs = msSince(t0);
      row.c2fIou = pipeline::maskIou(c2f, truthMask);
      if (size.area() <= 4'000'000 || fullGrabCut) {
        t0 = Clock::now();
        const cv::Mat full = pipeline::grabCutFullResolution(dressed, trimap);
        row.fullMs = msSince(t0);
        row.fullIou = pipeline::maskIou(full, truthMask);
      }
      grabRows.push_back(row);
    }
    std::printf("\n%-10s %12s %12s %7s %9s %9s\n", "grabcut", "c2f_ms", "full_ms", "ratio",
                "c2f_IoU", "full_IoU");
    for (const auto& r : grabRows) {
      if (r.fullMs < 0) {
        std::printf("%4dx%-5d %12.0f %12s %7s %9.4f %9s\n", r.size.width, r.size.height, r.c2fMs,
                    "-", "-", r.c2fIou, "-");
      } else {
        std::printf("%4dx%-5d %12.0f %12.0f %6.1fx %9.4f %9.4f\n", r.size.width, r.size.height,
                    r.c2fMs, r.fullMs, r.fullMs / r.c2fMs, r.c2fIou, r.fullIou);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pipeline_bench: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
