#include "garmcap/pipeline/image_files.h"

#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

namespace garmcap::pipeline {

namespace {

// The photos shops show are JPEG on white (full resolution PNGs run to tens of MB, and shops
// recompress them anyway); the cut-out keeps its alpha in PNG, the review masks stay lossless.
bool isShopPhoto(const std::string& kind) {
  return kind == "product" || kind == "product_4x5" || kind == "product_back" ||
         kind == "product_back_4x5" || kind == "product_ghost" || kind == "product_ghost_4x5";
}

std::string encode(const char* ext, const cv::Mat& image, const std::vector<int>& params,
                   const char* format) {
  std::vector<unsigned char> buf;
  if (!cv::imencode(ext, image, buf, params))
    throw std::runtime_error(std::string("cannot encode a ") + format + " image");
  return std::string(buf.begin(), buf.end());
}

// The same photos as WebP too, stored beside the JPEG as "<kind>_webp": shops that take WebP
// serve them a quarter to a third smaller. Quality 88 looks as the JPEG at 90 does (SSIM of the
// luma within 0.003 of it, PSNR higher; tests/bench/product_photo_bench's second table).
constexpr int kWebpQuality = 88;

}  // namespace

std::string encodePng(const cv::Mat& image) {
  return encode(".png", image, {}, "PNG");  // no level: OpenCV's fast path (image_files.h)
}

bool canWriteWebp() {
  static const bool yes = cv::haveImageWriter(".webp");
  return yes;
}

std::vector<EncodedImage> encodeImageFiles(const std::string& kind, const cv::Mat& image) {
  std::vector<EncodedImage> out;
  if (image.empty())
    return out;
  if (!isShopPhoto(kind)) {
    out.push_back({kind, "image/png", kind + ".png", encodePng(image)});
    return out;
  }
  out.push_back({kind, "image/jpeg", kind + ".jpg",
                 encode(".jpg", image, {cv::IMWRITE_JPEG_QUALITY, 90, cv::IMWRITE_JPEG_OPTIMIZE, 1},
                        "JPEG")});
  if (canWriteWebp())
    out.push_back({kind + "_webp", "image/webp", kind + ".webp",
                   encode(".webp", image, {cv::IMWRITE_WEBP_QUALITY, kWebpQuality}, "WebP")});
  return out;
}

cv::Mat decodeImageBytes(const std::string& bytes, const std::string& what) {
  cv::Mat raw(1, static_cast<int>(bytes.size()), CV_8U, const_cast<char*>(bytes.data()));
  cv::Mat img = cv::imdecode(raw, cv::IMREAD_COLOR);
  if (img.empty())
    throw std::runtime_error("cannot decode the stored " + what);
  return img;
}

}  // namespace garmcap::pipeline
