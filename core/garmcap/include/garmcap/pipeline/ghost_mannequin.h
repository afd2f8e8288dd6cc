#pragma once
// The "ghost mannequin" front photo: the garment photographed on the form a second time, turned
// back to front, gives the inside of its back, which is laid into the front photo's neck opening
// where the form (or, beyond its neck, the background) showed. Both shots are registered onto the
// same bare-form frame, so the form's vertical axis in that frame is the mirror line that maps
// the back shot onto the front one. docs/formats.md ("Back shot and ghost mannequin") defines the
// neck opening and gives the numbers.

#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "garmcap/pipeline/product_images.h"

namespace garmcap::pipeline {

/// How much the inside of the back is darkened: each BGR value times this (the inside is in the
/// garment's shade; a mid grey, sRGB 128, goes to 102: about 10 L* darker).
inline constexpr double kGhostInsideShade = 0.8;

/// An opening deeper than this share of the garment's height is an open front (a cardigan, a
/// wrap), not a neckline: no neck opening.
inline constexpr double kMaxNeckOpeningDepth = 0.5;

/// A back shot's garment area may differ from the front's by this share of the front's area; beyond
/// it, the back shot shows another garment (or one hung differently) and is refused. The same
/// garment turned round differs by its necklines (the back's, higher, fills the front's opening):
/// +2.9 % for the rig test's top (10 cm front, 2 cm back neckline); a dress shot as the back of
/// that top differs by +69.8 %. A look-alike of the same cut and size passes: this check is for a
/// wrong garment type or size, or a garment off the form.
inline constexpr double kBackAreaTolerance = 0.15;

struct NeckOpening {
  cv::Mat1b region;     // 255 inside the opening; empty when there is none
  std::string whyNone;  // a sentence when `region` is empty
};

/// The neck opening of a garment mask (CV_8U, non-zero = garment) whose wearer's vertical axis is
/// column `axisX`. The left neck point is the highest garment pixel left of the axis (of those,
/// the one nearest the axis), the right one likewise; the lid is the straight segment between
/// them. The opening is every non-garment pixel strictly between the two neck points' columns and
/// below the lid that is 4-connected through non-garment pixels to the row just below the lid: the
/// area the garment's outline encloses above its neckline. None when a side has no garment, when
/// the region is empty, or when it reaches deeper than kMaxNeckOpeningDepth of the garment's height
/// (not enclosed: an open front).
NeckOpening neckOpening(const cv::Mat1b& garment, double axisX);

/// `layer` mirrored about column `axisX` of the frame, sampled on the grid of the rectangle `to`
/// of the frame, where `from` is the rectangle of the frame `layer` covers: pixel (x, y) of the
/// result is the layer at frame column 2 axisX - (to.x + x), row to.y + y (bilinear; outside the
/// layer: colour 0, alpha 0).
ProductLayer mirroredLayer(const ProductLayer& layer, const cv::Rect& from, double axisX,
                           const cv::Rect& to);

/// Lays `inside` (the back's layer, already mirrored onto `front`'s grid) behind `front` within
/// `opening` (the front's neck opening on the same grid) and within `rimPx` of it where the
/// front's alpha is below 1 (the soft neckline edge): front over the inside, darkened by
/// kGhostInsideShade, over white. Straight alpha: a = af + (1 - af) ai,
/// colour = (af F + (1 - af) ai shade B) / a. Pixels elsewhere, and fully covered front pixels,
/// keep their bytes. Returns the number of pixels changed.
int composeGhostFront(ProductLayer& front, const ProductLayer& inside, const cv::Mat1b& opening,
                      int rimPx);

}  // namespace garmcap::pipeline
