#include "garmcap/pipeline/image_files.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <thread>

#ifdef GARMCAP_HAVE_LIBWEBP
#include <webp/encode.h>
#endif

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

#ifdef GARMCAP_HAVE_LIBWEBP
int appendToString(const std::uint8_t* data, std::size_t size, const WebPPicture* picture) {
  static_cast<std::string*>(picture->custom_ptr)->append(reinterpret_cast<const char*>(data), size);
  return 1;
}
#endif

// One encoding of one image: what encodeImageFiles makes, as a task of its own.
struct Job {
  const cv::Mat* image;
  std::string kind;
  enum class Format { kPng, kJpeg, kWebp } format;
};

std::vector<Job> jobsFor(const std::string& kind, const cv::Mat& image) {
  std::vector<Job> jobs;
  if (image.empty())
    return jobs;
  if (!isShopPhoto(kind)) {
    jobs.push_back({&image, kind, Job::Format::kPng});
    return jobs;
  }
  jobs.push_back({&image, kind, Job::Format::kJpeg});
  if (canWriteWebp())
    jobs.push_back({&image, kind, Job::Format::kWebp});
  return jobs;
}

EncodedImage run(const Job& job) {
  switch (job.format) {
    case Job::Format::kPng:
      return {job.kind, "image/png", job.kind + ".png", encodePng(*job.image)};
    case Job::Format::kJpeg:
      return {job.kind, "image/jpeg", job.kind + ".jpg",
              encode(".jpg", *job.image,
                     {cv::IMWRITE_JPEG_QUALITY, 90, cv::IMWRITE_JPEG_OPTIMIZE, 1}, "JPEG")};
    case Job::Format::kWebp:
      return {job.kind + "_webp", "image/webp", job.kind + ".webp",
              encodeWebp(*job.image, kWebpQuality, kWebpMethod)};
  }
  throw std::logic_error("unknown image format");
}

}  // namespace

std::string encodePng(const cv::Mat& image) {
  return encode(".png", image, {}, "PNG");  // no level: OpenCV's fast path (image_files.h)
}

bool canWriteWebp() {
#ifdef GARMCAP_HAVE_LIBWEBP
  return true;
#else
  static const bool yes = cv::haveImageWriter(".webp");
  return yes;
#endif
}

std::string encodeWebp(const cv::Mat& bgr, int quality, int method) {
  if (bgr.empty() || bgr.type() != CV_8UC3)
    throw std::runtime_error("cannot encode a WebP image: not an 8-bit BGR image");
#ifdef GARMCAP_HAVE_LIBWEBP
  // libwebp's own API, as OpenCV calls it (WebPEncodeBGR: the default preset at this quality)
  // but with the method set: OpenCV always takes libwebp's default, 4.
  WebPConfig config;
  if (!WebPConfigPreset(&config, WEBP_PRESET_DEFAULT, static_cast<float>(quality)))
    throw std::runtime_error("cannot encode a WebP image: libwebp's version does not match");
  config.method = method;
  if (!WebPValidateConfig(&config))
    throw std::runtime_error("cannot encode a WebP image: quality " + std::to_string(quality) +
                             " or method " + std::to_string(method) + " out of range");
  WebPPicture picture;
  if (!WebPPictureInit(&picture))
    throw std::runtime_error("cannot encode a WebP image: libwebp's version does not match");
  picture.width = bgr.cols;
  picture.height = bgr.rows;
  std::string out;
  picture.writer = appendToString;
  picture.custom_ptr = &out;
  const bool ok = WebPPictureImportBGR(&picture, bgr.data, static_cast<int>(bgr.step)) &&
                  WebPEncode(&config, &picture);
  const int error = picture.error_code;
  WebPPictureFree(&picture);
  if (!ok)
    throw std::runtime_error("cannot encode a WebP image (libwebp error " + std::to_string(error) +
                             ")");
  return out;
#else
  (void)method;  // OpenCV's encoder takes libwebp's default method, 4
  return encode(".webp", bgr, {cv::IMWRITE_WEBP_QUALITY, quality}, "WebP");
#endif
}

std::vector<EncodedImage> encodeImageFiles(const std::string& kind, const cv::Mat& image) {
  std::vector<EncodedImage> out;
  for (const Job& job : jobsFor(kind, image))
    out.push_back(run(job));
  return out;
}

std::vector<EncodedImage> encodeImageSet(
    const std::vector<std::pair<std::string, cv::Mat>>& images) {
  std::vector<Job> jobs;
  for (const auto& [kind, image] : images)
    for (Job& job : jobsFor(kind, image))
      jobs.push_back(std::move(job));
  // Each encoder is single-threaded (zlib, libjpeg, libwebp as called here); the photos, the
  // cut-out and the overlay are the long ones. They are taken longest first (by pixels times a
  // rough cost per pixel) by the calling thread and as many helpers as OpenCV's pool has
  // threads less one, so the short ones fill in behind the long ones.
  auto cost = [](const Job& j) {
    const double px = static_cast<double>(j.image->total()) * j.image->channels();
    return j.format == Job::Format::kWebp ? 4 * px : px;
  };
  std::vector<std::size_t> order(jobs.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return cost(jobs[a]) > cost(jobs[b]); });
  std::vector<EncodedImage> out(jobs.size());
  std::vector<std::exception_ptr> failed(jobs.size());
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t k = next++; k < order.size(); k = next++) {
      const std::size_t i = order[k];
      try {
        out[i] = run(jobs[i]);
      } catch (...) {
        failed[i] = std::current_exception();
      }
    }
  };
  const std::size_t threadsWanted =
      std::min(order.size(), static_cast<std::size_t>(std::max(1, cv::getNumThreads())));
  const std::size_t helpers = threadsWanted > 0 ? threadsWanted - 1 : 0;
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < helpers; ++t)
    threads.emplace_back(work);
  work();
  for (std::thread& t : threads)
    t.join();
  // The first failure in the sets' order is the one reported, as one by one.
  for (const std::exception_ptr& e : failed)
    if (e)
      std::rethrow_exception(e);
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
