#pragma once
// One-repeat texture of the garment's fabric (seed §5.2.5). Lines of stripes and checks are found
// with a Sobel filter and traced across the fabric; a triangle mesh built on them is straightened
// by deformation transfer (Sumner & Popović 2004: smoothness E_S + identity E_I, with every line's
// vertices merged into one unknown so the system stays SPD, and the outermost two lines pinned so
// the grid cannot shrink, ../shared/research/anchors_algorithms.md §5); the straightened patch is
// cut to one repeat. Solid fabrics give a swatch of their median colour.

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "garmcap/drafts/fabric_kind.h"

namespace garmcap::pipeline {

// The kind of fabric, named as the simulator names it (drafts::fabricKindName). The texture is
// read as solid, stripes or checks; a print is taken for solid (its swatch is its median colour).
using drafts::FabricKind;

struct TextureResult {
  FabricKind kind = FabricKind::kSolid;
  cv::Mat tile;             // BGR one-repeat tile (solid: a 64x64 swatch)
  cv::Vec3b meanColour;     // median colour of the fabric, BGR
  double periodXPx = 0;     // repeat along x in the straightened patch (0: none)
  double periodYPx = 0;     // repeat along y (0: none)
  int horizontalLines = 0;  // lines traced before straightening
  int verticalLines = 0;
};

/// Traced lines of one orientation in a patch: each line is its y at every strip centre.
struct TracedLines {
  std::vector<double> stripX;              // x of the strip centres
  std::vector<std::vector<double>> lineY;  // [line][strip], lines sorted top to bottom
};

/// Finds and traces horizontal-ish lines (intensity edges) across `grey` (CV_32F). Lines that do
/// not span the strips shared by all are dropped. Empty when fewer than 3 lines are found.
TracedLines traceHorizontalLines(const cv::Mat& grey, int stripWidthPx = 12);

/// Straightens the horizontal lines of `bgr` by deformation transfer on the mesh of `lines`.
/// Returns the straightened image covering the mesh, or nullopt when the solve fails or folds.
std::optional<cv::Mat> straightenHorizontal(const cv::Mat& bgr, const TracedLines& lines);

/// The texture of the fabric inside `mask` (CV_8U, non-zero = garment) of `bgr`.
/// Throws std::invalid_argument when the mask is empty.
TextureResult extractTexture(const cv::Mat& bgr, const cv::Mat& mask);

}  // namespace garmcap::pipeline
