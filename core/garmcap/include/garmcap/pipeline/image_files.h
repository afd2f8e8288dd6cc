#pragma once
// How a capture's images are written, by the station into its store and by `garmcap capture
// --out` into a folder alike: the camera's stills and the review masks lossless (PNG), the
// photos shops show as JPEG on white with a WebP copy beside them, the cut-out as PNG (it keeps
// its alpha). One place decides the encoding of every kind, so the station's blobs, the CLI's
// files and the exports agree.

#include <opencv2/core/mat.hpp>
#include <string>
#include <utility>
#include <vector>

namespace garmcap::pipeline {

/// One encoding of an image: the item's image kind ("product", "product_webp", ...), its media
/// type, the file name it is written as outside the store, and the bytes.
struct EncodedImage {
  std::string kind;
  std::string mediaType;
  std::string fileName;
  std::string bytes;
};

/// Lossless PNG, encoded for speed: OpenCV 4.6 given no compression level uses one row filter
/// (Sub) at zlib level 1, instead of trying every filter on every row as it does once a level is
/// set. Against level 1 with every filter (`product_photo_bench`, third table, one run): the
/// camera frame, the cut-out, the review overlay and the silhouette in 0.28-0.40 of the time and
/// 0.40-0.94 of the bytes, at 864x1152 and 3000x4000 (the 12 MP frame 1633 -> 573 ms).
/// Throws std::runtime_error if OpenCV cannot encode the image.
std::string encodePng(const cv::Mat& image);

/// Whether WebP can be written: always when built with libwebp (GARMCAP_HAVE_LIBWEBP), else when
/// this OpenCV writes it (Debian's links libwebp). Without it the photos are JPEG only.
bool canWriteWebp();

/// The WebP copies' quality and libwebp method (0 fastest .. 6 smallest). Quality 88 looks as the
/// JPEG at 90 does (SSIM of the luma within 0.003 of it, PSNR higher) at a quarter to a third
/// fewer bytes (tests/bench/product_photo_bench, second table). OpenCV's encoder always takes
/// method 4, 0.6-0.7 s a photo at 2048 px here; method 2 encodes a 12 MP capture's 2048 px photo
/// in 0.38 of its instructions (callgrind, WebPEncode: 0.89 vs 2.33 G) at 1 % more bytes and an
/// SSIM 0.001 lower (0.9684 vs 0.9693; the JPEG 0.9722); method 1 would take 0.25 at 8 % more.
constexpr int kWebpQuality = 88;
constexpr int kWebpMethod = 2;

/// `bgr` (8-bit, 3 channels) as lossy WebP at this quality (0-100) and method (0-6), by libwebp's
/// own API when built with it; otherwise by OpenCV, which ignores `method` (always 4). With
/// method 4 the bytes equal OpenCV's. Throws std::runtime_error if it cannot be encoded.
std::string encodeWebp(const cv::Mat& bgr, int quality, int method);

/// The encodings of a pipeline image of this kind: "product" and "product_4x5" as JPEG
/// (quality 90; product.jpg) plus "<kind>_webp" as WebP (quality 88; product.webp) when
/// canWriteWebp(); every other kind as PNG (cutout.png). An empty image has none. Throws
/// std::runtime_error if an encoding fails.
std::vector<EncodedImage> encodeImageFiles(const std::string& kind, const cv::Mat& image);

/// encodeImageFiles of every (kind, image), in that order, the encodings side by side on up to
/// cv::getNumThreads() threads (each encoder is single-threaded; a capture's set is a dozen of
/// them). The same bytes as one by one. Throws the first failure in that order.
std::vector<EncodedImage> encodeImageSet(
    const std::vector<std::pair<std::string, cv::Mat>>& images);

/// Decodes stored bytes into BGR. Throws std::runtime_error naming `what` if they are not an
/// image OpenCV reads.
cv::Mat decodeImageBytes(const std::string& bytes, const std::string& what);

}  // namespace garmcap::pipeline
