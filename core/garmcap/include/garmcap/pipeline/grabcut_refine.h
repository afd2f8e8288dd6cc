#pragma once
// GrabCut made fast for 4-12 MP frames: learn the colour models and cut at about 0.1 MP, then
// re-cut only a thin band around the upsampled boundary at full resolution with the models
// frozen, as one graph over the band's undecided pixels. Plain full-resolution GrabCut costs
// seconds per iteration at 2-4 MP on 2 cores (../shared/research/anchors_algorithms.md §4); the
// band holds a few percent of the pixels.

#include <opencv2/core.hpp>

namespace garmcap::pipeline {

struct CoarseToFineOptions {
  double workMegapixels = 0.12;  // resolution of the coarse GrabCut
  int iterations = 3;            // GrabCut iterations at the coarse level (with 2 the models were
                                 // not settled on a 12 MP frame: IoU 0.976 against 0.992)
  int minBandPx = 6;             // half-width of the refinement band at full resolution (at least
                                 // twice the upsampling factor, see .cpp)
};

/// Garment mask from a trimap.
/// `bgr`: CV_8UC3 frame. `trimap`: CV_8UC1 of the same size with values cv::GC_BGD, cv::GC_FGD,
/// cv::GC_PR_BGD, cv::GC_PR_FGD only; it must hold at least one background-ish and one
/// foreground-ish pixel. Hard labels (GC_BGD/GC_FGD) are never changed.
/// Returns CV_8UC1, 255 = garment (foreground), 0 = not. Throws std::invalid_argument on bad
/// shapes or labels (a caller bug: the pipeline builds the trimap itself).
cv::Mat grabCutCoarseToFine(const cv::Mat& bgr, const cv::Mat& trimap,
                            const CoarseToFineOptions& options = {});

/// One GrabCut iteration with frozen colour models (`bgdModel`, `fgdModel`: the 1x65 CV_64F
/// models cv::grabCut returns): decides every GC_PR_* pixel of `labels` and returns the new
/// labels. The graph holds the undecided pixels only, with hard neighbours folded into terminal
/// weights, so it costs in proportion to them, not to the frame. The energy and maxflow are
/// cv::grabCut's; its edge-contrast scale beta is taken over the 256 px cells holding undecided
/// pixels (see .cpp), so where those cells cover the frame the cut is exactly the one
/// cv::grabCut(GC_EVAL_FREEZE_MODEL) makes on the whole frame.
/// Throws std::invalid_argument on bad shapes, labels or models.
cv::Mat grabCutFrozen(const cv::Mat& bgr, const cv::Mat& labels, const cv::Mat& bgdModel,
                      const cv::Mat& fgdModel);

/// The baseline the benchmark compares against: plain cv::grabCut on the whole frame with the
/// same trimap and `iterations` iterations. Same contract as above.
cv::Mat grabCutFullResolution(const cv::Mat& bgr, const cv::Mat& trimap, int iterations = 3);

/// Intersection over union of two binary masks (non-zero = set). 1 when both are empty.
double maskIou(const cv::Mat& a, const cv::Mat& b);

}  // namespace garmcap::pipeline
