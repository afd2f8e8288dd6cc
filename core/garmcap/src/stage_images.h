#pragma once
// Stage 8 of a capture: the images, from the garment's part of the full frame only: the review
// overlay, the product photos and the fabric's texture (internal).

#include <opencv2/core.hpp>

#include "bare_frame.h"
#include "garmcap/calib/chroma_key.h"
#include "garmcap/pipeline/capture_context.h"
#include "garmcap/pipeline/capture_pipeline.h"
#include "garmcap/pipeline/garment_measurer.h"
#include "garmcap/pipeline/product_images.h"
#include "stage_timer.h"

namespace garmcap::pipeline {

struct CaptureImagesInput {
  const cv::Mat& dressedFull;             // the full dressed frame, upright and registered
  const cv::Mat& dressedWork;             // the dressed work frame (the overlay is drawn on it)
  double workScale;                       // work frame px per full frame px
  const cv::Mat& garment;                 // the garment's mask on it
  const GarmentMeasurement& measurement;  // its landmarks, for the overlay
  const BareFrame& bare;                  // what the form looked like (the photos' background)
  const cv::Vec3b& screenBgr;             // the screen's colour in the dressed frame
};

/// The front photos' layer (what makeProductImages composited) and where its crop lies in the
/// upright, registered full frame; empty when no product images were made.
struct PhotoLayer {
  ProductLayer layer;
  cv::Rect box;
};

/// The product photos' options for a frame of `frame` size, as the capture asks them.
ProductImageOptions productImageOptions(const CaptureOptions& options, cv::Size frame,
                                        double pxPerCm);

/// The garment's box with a 2 cm margin, within the frame: the part the photos are made from.
cv::Rect photoBox(const cv::Mat& garment, double pxPerCm);

/// Sets `result`'s silhouette, overlay (at the work frame's size), and as `options` ask the product
/// photos and the texture (with the fabric attribute); ends the timer's "images" and "texture"
/// stages. Returns the front photos' layer for a back shot (stage_back_shot.h).
PhotoLayer makeCaptureImages(const CaptureContext& ctx, const CaptureImagesInput& in,
                             const CaptureOptions& options, StageTimer& timer,
                             CaptureResult& result);

}  // namespace garmcap::pipeline
