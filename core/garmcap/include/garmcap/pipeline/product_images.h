#pragma once
// Product photos from a garment mask: the garment cut out with a soft alpha edge (form and
// background removed; the inside of the neck from a back shot: ghost_mannequin.h), centred and
// cropped, on white and on transparent, at the camera frame's own resolution.
//
// The mask comes from segmentation (placed to the pixel against the screen, upsampled from the
// work frame against the form). Here, at full resolution and only in a narrow band along its
// outline:
//  - the edge is refined with a guided filter on the frame (alpha follows the garment's own
//    edge, not the mask's stair steps);
//  - whatever still looks as it did in the bare-form frame and reaches the outline through such
//    pixels is form or background, not garment, and is cut (a sliver of form in a crotch, a rim
//    at a waistband or round a neckline);
//  - green-screen spill is removed: the part of an edge pixel's chroma that points from the
//    garment's inside chroma towards the screen's chroma is taken out (lightness kept).

#include <opencv2/core.hpp>
#include <optional>

namespace garmcap::pipeline {

struct ProductImageOptions {
  int maxSidePx = 4096;  // longest side of a photo; larger crops are scaled down
  int minSidePx = 0;     // shortest longest side: a smaller crop is scaled up to it, by 1.5x at
                         // most (shops zoom from 2048 px; beyond 1.5x it would be blur, not
                         // fabric). The pipeline asks 2048 when the frame's long side has it.
  double marginFraction = 0.06;  // empty border around the garment, per side
  double pxPerCm = 0;            // frame px per cm (productPhotos: required, > 0)
  // A soft drop shadow under the garment on the white photos (not the cut-out): its alpha
  // shrunk, moved down and blurred, at a modest opacity, behind the garment. Off by default:
  // marketplaces that ask for a pure white background (RGB 255) refuse a main image with one,
  // and a theme that lays the photo on a tint shows its grey; docs/exports.md.
  bool shadow = false;
  // productLayer: the form-remains test and the despill's Lab conversions over the whole crop,
  // as before they were kept to the pixels near the outline (the same layer, slower); kept for
  // the identity test (ProductPhotoRig.LayerNearTheOutlineEqualsTheWholeCropPasses).
  bool wholeCropPasses = false;
};

/// BGRA cut-out of the whole frame: colour from `bgr`, alpha from `mask` (CV_8U, non-zero =
/// garment) with a feathered edge. Throws std::invalid_argument on mismatched inputs.
cv::Mat makeCutout(const cv::Mat& bgr, const cv::Mat& mask, double featherPx = 1.5);

/// Alpha 0..1 (CV_32F) from a binary mask, refined by a grey-level guided filter of radius
/// `radiusPx` over `bgr` within `radiusPx` of the mask's outline; elsewhere 0 or 1 as the mask.
cv::Mat1f refinedAlpha(const cv::Mat3b& bgr, const cv::Mat1b& mask, int radiusPx);

/// What looks as the registered bare-form frame `bare` did and reaches the outside of `mask`
/// through such pixels: form or background, not garment. Inside the mask only within `bandPx`
/// of its outline (deeper is the garment's own, however it looks); outside it as well (where a
/// soft edge may reach). A pixel looks as the bare frame did when it differs from it by less than
/// `maxDeltaE` (CIELAB, after a light blur of both) and is nearer to it than to the garment's
/// colour a few px inside the outline, or is less than half as far from it as from that colour
/// where that colour is clearly unlike it (more than 2 maxDeltaE). With the screen's colour
/// `screenBgr`, also form the dressed frame's spill tints: within 2 maxDeltaE of the bare frame,
/// nearer to it than to the garment's colour, and once its shift towards the screen's colour is
/// taken out, less than maxDeltaE from it and less than maxDeltaE / 2 towards the garment's colour.
cv::Mat1b formRemains(const cv::Mat3b& dressed, const cv::Mat3b& bare, const cv::Mat1b& mask,
                      double bandPx, double maxDeltaE,
                      const std::optional<cv::Vec3b>& screenBgr = std::nullopt);

/// Removes green-screen spill from `bgr` where `alpha` > 0 within `bandPx` of the alpha's outline:
/// each pixel's CIELAB chroma loses its component along the direction from the garment's inside
/// chroma near it (a blur of the chroma found deeper than `bandPx`) towards the screen's chroma.
/// Lightness and chroma in other directions stay.
void despillEdge(cv::Mat3b& bgr, const cv::Mat1f& alpha, const cv::Vec3b& screenBgr, double bandPx);

/// The drop shadow's darkness (0 = none, 1 = black) on a canvas where the garment's alpha
/// `canvasAlpha` (CV_32F 0..1) lies as composited: the alpha shrunk, moved down and blurred by
/// fractions of the garment's height, times a modest opacity. It falls below 1/512 (rounds to
/// white) within the photos' margin to the left, right and top, and below the hem within it.
cv::Mat1f dropShadow(const cv::Mat1f& canvasAlpha);

struct ProductImages {
  cv::Mat cutout;       // BGRA, the garment's box with a margin, full resolution (PNG)
  cv::Mat square;       // BGR on white, 1:1, garment centred with the margin (the shop photo)
  cv::Mat portrait;     // BGR on white, 4:5 (width:height), garment centred with the margin
  cv::Rect garmentBox;  // the garment's box in the input's pixels
  cv::Rect cutoutRect;  // where the cut-out lies in the input's pixels (before any downscaling)
};

/// The photos from the garment's colour `bgr` (despilled as wanted) and its alpha (CV_32F 0..1,
/// same size). Throws std::invalid_argument when the alpha is empty or sizes differ.
ProductImages makeProductImages(const cv::Mat3b& bgr, const cv::Mat1f& alpha,
                                const ProductImageOptions& options = {});

/// The garment as the photos composite it: its colour (edge unmixed and despilled) and its alpha
/// (CV_32F 0..1), both of the input's size.
struct ProductLayer {
  cv::Mat3b colour;
  cv::Mat1f alpha;
};

/// The chain before the photos (productPhotos without makeProductImages): refined alpha, form
/// remains cut against `bare` (may be empty), edge unmixed and despilled against `screenBgr`.
ProductLayer productLayer(const cv::Mat3b& dressed, const cv::Mat1b& mask, const cv::Mat3b& bare,
                          const cv::Vec3b& screenBgr, const ProductImageOptions& options);

/// The whole chain on the garment's part of the frame: refined alpha, form remains cut against
/// `bare` (may be empty: no cut), edge despilled against `screenBgr`, the photos made.
/// `bare` and `mask` must have `dressed`'s size. Band widths scale with options.pxPerCm.
ProductImages productPhotos(const cv::Mat3b& dressed, const cv::Mat1b& mask, const cv::Mat3b& bare,
                            const cv::Vec3b& screenBgr, const ProductImageOptions& options);

}  // namespace garmcap::pipeline
