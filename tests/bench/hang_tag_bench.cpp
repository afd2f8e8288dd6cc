// The hang-tag scan alone on a still: the scan before issue 16 (zbar over the whole frame in grey,
// as daemon/src/pipeline_processor.cpp did) against decodeHangTagSku (zbar over
// hangTagScanImage). Prints the median wall and CPU time of each, what each read, and the region
// scanned. Usage: hang_tag_bench STILL.png [--bare BARE_FORM.png] [--reps N]. No assertions: the
// reads are tested in tests/daemon/sku_barcode_test.cpp and sku_test.cpp.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "garmcap/daemon/capture_processor.h"

namespace {

double cpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) / 1e6;
}

// The scan as it was: zbar over the whole frame's grey.
std::string wholeFrameScan(const cv::Mat& bgr) {
  cv::Mat grey;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  return garmcap::daemon::decodeSkuInGrey(grey);
}

template <class F>
void timeIt(const char* name, int reps, F&& f) {
  std::vector<double> wall, cpu;
  std::string got;
  for (int i = 0; i < reps; ++i) {
    const auto w0 = std::chrono::steady_clock::now();
    const double c0 = cpuMs();
    got = f();
    cpu.push_back(cpuMs() - c0);
    wall.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - w0).count());
  }
  std::sort(wall.begin(), wall.end());
  std::sort(cpu.begin(), cpu.end());
  std::printf("%-34s median wall %6.1f ms  CPU %6.1f ms  (%d reps)  read '%s'\n", name,
              wall[wall.size() / 2], cpu[cpu.size() / 2], reps, got.c_str());
}

}  // namespace

int main(int argc, char** argv) {
#ifndef GARMCAP_HAVE_ZBAR
  std::printf("built without zbar (libzbar-dev): nothing to time\n");
  return argc > 0 ? 0 : 1;
#else
  if (argc < 2 || std::string(argv[1]) == "--help") {
    std::printf("usage: hang_tag_bench STILL.png [--bare BARE_FORM.png] [--reps N]\n");
    return argc < 2 ? 2 : 0;
  }
  int reps = 7;
  std::string barePath;
  for (int i = 2; i + 1 < argc; ++i) {
    if (std::string(argv[i]) == "--reps")
      reps = std::max(1, std::stoi(argv[i + 1]));
    if (std::string(argv[i]) == "--bare")
      barePath = argv[i + 1];
  }
  const cv::Mat bgr = cv::imread(argv[1], cv::IMREAD_COLOR);
  if (bgr.empty())
    throw std::runtime_error(std::string("cannot read ") + argv[1]);
  cv::Mat bare;
  if (!barePath.empty() && (bare = cv::imread(barePath, cv::IMREAD_COLOR)).empty())
    throw std::runtime_error("cannot read " + barePath);
  auto regionOf = [&](const cv::Mat& b, const char* what) {
    cv::Rect region;
    garmcap::daemon::hangTagScanImage(bgr, &region, b);
    std::printf("still %dx%d, %s: scanned region %dx%d at (%d,%d), %.0f%% of the frame\n", bgr.cols,
                bgr.rows, what, region.width, region.height, region.x, region.y,
                100.0 * region.area() / static_cast<double>(bgr.total()));
  };
  regionOf(cv::Mat(), "without the bare frame");
  if (!bare.empty())
    regionOf(bare, "with the bare frame");
  timeIt("whole frame (before issue 16)", reps, [&] { return wholeFrameScan(bgr); });
  timeIt("hangTagScanImage, no bare frame", reps, [&] {
    garmcap::daemon::hangTagScanImage(bgr);
    return std::string();
  });
  timeIt("decodeHangTagSku, no bare frame", reps,
         [&] { return garmcap::daemon::decodeHangTagSku(bgr); });
  if (!bare.empty()) {
    timeIt("hangTagScanImage, bare frame", reps, [&] {
      garmcap::daemon::hangTagScanImage(bgr, nullptr, bare);
      return std::string();
    });
    timeIt("decodeHangTagSku, bare frame", reps,
           [&] { return garmcap::daemon::decodeHangTagSku(bgr, bare); });
  }
  return 0;
#endif
}
