#include "garmcap/pipeline/grabcut_refine.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

namespace garmcap::pipeline {
namespace {

// OpenCV's label enum as plain numbers: comparing cv::Mat with an enum converts it to double,
// which C++20 deprecates.
constexpr int kBgd = cv::GC_BGD;
constexpr int kFgd = cv::GC_FGD;
constexpr int kPrBgd = cv::GC_PR_BGD;
constexpr int kPrFgd = cv::GC_PR_FGD;

void checkInputs(const cv::Mat& bgr, const cv::Mat& trimap) {
  if (bgr.empty() || bgr.type() != CV_8UC3)
    throw std::invalid_argument("grabCut: frame must be a non-empty 8-bit BGR image");
  if (trimap.size() != bgr.size() || trimap.type() != CV_8UC1)
    throw std::invalid_argument("grabCut: trimap must be CV_8UC1 of the frame's size");
  double maxLabel = 0;
  cv::minMaxLoc(trimap, nullptr, &maxLabel);
  if (maxLabel > kPrFgd)
    throw std::invalid_argument(
        "grabCut: trimap holds a value other than GC_BGD/FGD/PR_BGD/PR_FGD");
}

bool hasBothClasses(const cv::Mat& trimap) {
  // GrabCut's k-means needs samples of both classes (CV_Assert in OpenCV's grabcut.cpp).
  const cv::Mat fg = (trimap == kFgd) | (trimap == kPrFgd);
  const int fgCount = cv::countNonZero(fg);
  return fgCount > 0 && fgCount < static_cast<int>(trimap.total());
}

// GrabCut seeds its k-means from OpenCV's thread-local RNG: fix it so a capture gives the same
// silhouette every time, whatever ran before on this thread.
void seedGrabCutRng() {
  cv::theRNG().state = 0x9e3779b97f4a7c15ULL;
}

cv::Mat foreground(const cv::Mat& labels) {
  return ((labels == kFgd) | (labels == kPrFgd));
}

}  // namespace

cv::Mat grabCutFullResolution(const cv::Mat& bgr, const cv::Mat& trimap, int iterations) {
  checkInputs(bgr, trimap);
  if (!hasBothClasses(trimap))
    return foreground(trimap);
  cv::Mat labels = trimap.clone();
  cv::Mat bgdModel, fgdModel;
  seedGrabCutRng();
  cv::grabCut(bgr, labels, cv::Rect(), bgdModel, fgdModel, std::max(1, iterations),
              cv::GC_INIT_WITH_MASK);
  return foreground(labels);
}

cv::Mat grabCutCoarseToFine(const cv::Mat& bgr, const cv::Mat& trimap,
                            const CoarseToFineOptions& options) {
  checkInputs(bgr, trimap);
  if (!hasBothClasses(trimap))
    return foreground(trimap);

  const double megapixels = static_cast<double>(bgr.total()) / 1e6;
  const double scale = std::min(1.0, std::sqrt(options.workMegapixels / megapixels));
  if (scale > 0.9)
    return grabCutFullResolution(bgr, trimap, options.iterations);

  // 1. Coarse GrabCut: INTER_AREA keeps colours faithful, INTER_NEAREST keeps labels valid.
  cv::Mat smallBgr, smallLabels;
  cv::resize(bgr, smallBgr, cv::Size(), scale, scale, cv::INTER_AREA);
  cv::resize(trimap, smallLabels, smallBgr.size(), 0, 0, cv::INTER_NEAREST);
  cv::Mat bgdModel, fgdModel;
  if (!hasBothClasses(smallLabels))
    return foreground(trimap);
  seedGrabCutRng();
  cv::grabCut(smallBgr, smallLabels, cv::Rect(), bgdModel, fgdModel, options.iterations,
              cv::GC_INIT_WITH_MASK);

  // 2. Upsample the coarse decision; the boundary is uncertain by about one coarse pixel.
  cv::Mat coarseFg;
  cv::resize(foreground(smallLabels), coarseFg, bgr.size(), 0, 0, cv::INTER_LINEAR);
  cv::threshold(coarseFg, coarseFg, 127, 255, cv::THRESH_BINARY);

  // 3. Band around the boundary, wide enough to contain the upsampling error.
  const int halfWidth = std::max(options.minBandPx, static_cast<int>(std::ceil(2.0 / scale)));
  cv::Mat edges;
  cv::morphologyEx(coarseFg, edges, cv::MORPH_GRADIENT,
                   cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
  cv::Mat band;
  cv::dilate(
      edges, band,
      cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * halfWidth + 1, 2 * halfWidth + 1)));

  // Full-resolution labels: hard from the coarse cut outside the band, probable inside it, and
  // the caller's hard labels always win.
  cv::Mat labels(bgr.size(), CV_8UC1, cv::Scalar(kBgd));
  labels.setTo(kFgd, coarseFg);
  cv::Mat bandFg = band & coarseFg;
  cv::Mat bandBg = band & ~coarseFg;
  labels.setTo(kPrFgd, bandFg);
  labels.setTo(kPrBgd, bandBg);
  labels.setTo(kBgd, trimap == kBgd);
  labels.setTo(kFgd, trimap == kFgd);

  // 4. Refine the band tile by tile with the coarse colour models frozen. Tiles overlap by twice
  // the band width so that each boundary pixel is cut with context on both sides.
  const int tile = std::max(32, options.tilePx);
  const int overlap = 2 * halfWidth;
  struct Tile {
    cv::Rect withOverlap;
    cv::Rect core;
  };
  std::vector<Tile> tiles;
  // Only band pixels the caller left open need a cut: where its hard labels meet (the garment
  // against the green screen, say) the boundary is already decided.
  const cv::Mat open = (labels == kPrFgd) | (labels == kPrBgd);
  for (int y = 0; y < bgr.rows; y += tile) {
    for (int x = 0; x < bgr.cols; x += tile) {
      cv::Rect r(x - overlap, y - overlap, tile + 2 * overlap, tile + 2 * overlap);
      r &= cv::Rect(0, 0, bgr.cols, bgr.rows);
      const cv::Rect core(x, y, std::min(tile, bgr.cols - x), std::min(tile, bgr.rows - y));
      if (cv::countNonZero(open(core)) > 0)
        tiles.push_back({r, core});
    }
  }
  cv::Mat refined = labels.clone();
  cv::parallel_for_(cv::Range(0, static_cast<int>(tiles.size())), [&](const cv::Range& range) {
    for (int i = range.start; i < range.end; ++i) {
      const cv::Rect r = tiles[static_cast<std::size_t>(i)].withOverlap;
      const cv::Rect core = tiles[static_cast<std::size_t>(i)].core;
      cv::Mat tileLabels = labels(r).clone();
      cv::Mat bgd = bgdModel.clone();
      cv::Mat fgd = fgdModel.clone();
      cv::grabCut(bgr(r), tileLabels, cv::Rect(), bgd, fgd, 1, cv::GC_EVAL_FREEZE_MODEL);
      // Write back only the tile's own core (no overlap) so that tiles never race.
      tileLabels(core - r.tl()).copyTo(refined(core));
    }
  });
  return foreground(refined);
}

double maskIou(const cv::Mat& a, const cv::Mat& b) {
  CV_Assert(a.size() == b.size());
  const int inter = cv::countNonZero((a != 0) & (b != 0));
  const int uni = cv::countNonZero((a != 0) | (b != 0));
  return uni == 0 ? 1.0 : static_cast<double>(inter) / uni;
}

}  // namespace garmcap::pipeline
