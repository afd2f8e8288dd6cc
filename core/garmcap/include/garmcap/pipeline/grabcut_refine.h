#pragma once
// GrabCut made fast for 4-12 MP frames: learn the colour models and cut at about 0.5 MP, then
// re-cut only a thin band around the upsampled boundary at full resolution, in tiles, with the
// models frozen. Plain full-resolution GrabCut costs seconds per iteration at 2-4 MP on 2 cores
// (../shared/research/anchors_algorithms.md §4); the band holds a few percent of the pixels.

#include <opencv2/core.hpp>

namespace garmcap::pipeline {

struct CoarseToFineOptions {
  double workMegapixels = 0.12;  // resolution of the coarse GrabCut
  int iterations = 3;            // GrabCut iterations at the coarse level
  int minBandPx = 6;             // half-width of the refinement band at full resolution (at least
                                 // twice the upsampling factor, see .cpp)
  int tilePx = 256;              // edge of the refinement tiles: smaller ones hug the band (GrabCut
                                 // works on every pixel of a tile) but lose context: at 128 the cut
                                 // drifts from plain GrabCut (IoU 0.989 in grabcut_refine_test)
};

/// Garment mask from a trimap.
/// `bgr`: CV_8UC3 frame. `trimap`: CV_8UC1 of the same size with values cv::GC_BGD, cv::GC_FGD,
/// cv::GC_PR_BGD, cv::GC_PR_FGD only; it must hold at least one background-ish and one
/// foreground-ish pixel. Hard labels (GC_BGD/GC_FGD) are never changed.
/// Returns CV_8UC1, 255 = garment (foreground), 0 = not. Throws std::invalid_argument on bad
/// shapes or labels (a caller bug: the pipeline builds the trimap itself).
cv::Mat grabCutCoarseToFine(const cv::Mat& bgr, const cv::Mat& trimap,
                            const CoarseToFineOptions& options = {});

/// The baseline the benchmark compares against: plain cv::grabCut on the whole frame with the
/// same trimap and `iterations` iterations. Same contract as above.
cv::Mat grabCutFullResolution(const cv::Mat& bgr, const cv::Mat& trimap, int iterations = 3);

/// Intersection over union of two binary masks (non-zero = set). 1 when both are empty.
double maskIou(const cv::Mat& a, const cv::Mat& b);

}  // namespace garmcap::pipeline
