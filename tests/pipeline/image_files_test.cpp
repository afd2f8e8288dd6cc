// How a capture's images are encoded (image_files.h): the set side by side gives what one by one
// gives, and the WebP copies through libwebp's own API still decode to the photo.
#include "garmcap/pipeline/image_files.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

using namespace garmcap::pipeline;

namespace {

// A photo-like image: smooth shading, a few hard edges and a little noise (the encoders take
// different paths for flat, smooth and busy blocks).
cv::Mat3b photo(int w, int h, int seed) {
  cv::Mat3b img(h, w);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img(y, x) =
          cv::Vec3b(static_cast<uchar>(40 + (x * 150) / w), static_cast<uchar>(60 + (y * 120) / h),
                    static_cast<uchar>(200 - ((x + y) * 100) / (w + h)));
  cv::rectangle(img, cv::Rect(w / 4, h / 5, w / 2, h / 2), cv::Scalar(30, 30, 160), cv::FILLED);
  cv::circle(img, cv::Point(w / 2, h / 2), std::min(w, h) / 6, cv::Scalar(240, 240, 240),
             cv::FILLED);
  cv::Mat noise(img.size(), CV_8UC3);
  cv::theRNG().state = static_cast<std::uint64_t>(seed);
  cv::randu(noise, 0, 6);
  img += noise;
  return img;
}

}  // namespace

TEST(ImageFiles, SetGivesTheBytesOfOneByOneInItsOrder) {
  const cv::Mat3b product = photo(480, 480, 1), portrait = photo(480, 600, 2);
  cv::Mat cutout;
  cv::cvtColor(photo(300, 420, 3), cutout, cv::COLOR_BGR2BGRA);
  cv::Mat1b silhouette = cv::Mat1b::zeros(640, 480);
  cv::ellipse(silhouette, cv::Point(240, 320), cv::Size(120, 250), 0, 0, 360, 255, cv::FILLED);
  const std::vector<std::pair<std::string, cv::Mat>> images = {
      {"cutout", cutout},        {"overlay", photo(480, 640, 4)}, {"product", product},
      {"product_4x5", portrait}, {"silhouette", silhouette},      {"texture", cv::Mat()},
      {"product_back", product}};
  std::vector<EncodedImage> expected;
  for (const auto& [kind, image] : images)
    for (EncodedImage& e : encodeImageFiles(kind, image))
      expected.push_back(std::move(e));
  // cut-out, overlay, 2 x 2 photos, silhouette, back photo x 2 (no texture), WebP or not.
  ASSERT_EQ(expected.size(), canWriteWebp() ? 9u : 6u);
  for (int run = 0; run < 3; ++run) {  // the threads finish in a different order each time
    const std::vector<EncodedImage> got = encodeImageSet(images);
    ASSERT_EQ(got.size(), expected.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
      EXPECT_EQ(got[i].kind, expected[i].kind) << i;
      EXPECT_EQ(got[i].mediaType, expected[i].mediaType) << i;
      EXPECT_EQ(got[i].fileName, expected[i].fileName) << i;
      EXPECT_TRUE(got[i].bytes == expected[i].bytes) << expected[i].kind << " differs";
    }
  }
  EXPECT_TRUE(encodeImageSet({}).empty());
}

TEST(ImageFiles, WebpAtMethodFourIsWhatOpenCvWrites) {
  if (!canWriteWebp() || !cv::haveImageWriter(".webp"))
    GTEST_SKIP() << "no WebP writer in this OpenCV";
  const cv::Mat3b img = photo(400, 500, 5);
  std::vector<uchar> opencv;
  ASSERT_TRUE(cv::imencode(".webp", img, opencv, {cv::IMWRITE_WEBP_QUALITY, kWebpQuality}));
  const std::string ours = encodeWebp(img, kWebpQuality, 4);
  EXPECT_TRUE(ours == std::string(opencv.begin(), opencv.end()))
      << "libwebp's default preset at method 4 should be OpenCV's WebPEncodeBGR";
}

TEST(ImageFiles, WebpCopyDecodesToThePhoto) {
  if (!canWriteWebp())
    GTEST_SKIP() << "this build writes no WebP";
  const cv::Mat3b img = photo(640, 800, 6);
  const auto files = encodeImageFiles("product_4x5", img);
  ASSERT_EQ(files.size(), 2u);
  const EncodedImage& webp = files[1];
  EXPECT_EQ(webp.kind, "product_4x5_webp");
  EXPECT_EQ(webp.mediaType, "image/webp");
  EXPECT_EQ(webp.fileName, "product_4x5.webp");
  ASSERT_GT(webp.bytes.size(), 12u);
  EXPECT_EQ(webp.bytes.substr(0, 4), "RIFF");
  EXPECT_EQ(webp.bytes.substr(8, 4), "WEBP");
  const cv::Mat back = decodeImageBytes(webp.bytes, "WebP photo");
  ASSERT_EQ(back.size(), img.size());
  // Lossy, at a photo's quality: the JPEG beside it reads about the same.
  const cv::Mat jpeg = decodeImageBytes(files[0].bytes, "JPEG photo");
  EXPECT_GT(cv::PSNR(img, back), 33.0);
  EXPECT_GT(cv::PSNR(img, back), cv::PSNR(img, jpeg) - 3.0);
  // And less than the lossless image: the method changes the search, not what is kept.
  EXPECT_LT(webp.bytes.size(), encodePng(img).size());
}

TEST(ImageFiles, AFailingEncodingFailsTheSet) {
  if (!canWriteWebp())
    GTEST_SKIP() << "this build writes no WebP";
  EXPECT_THROW(encodeWebp(cv::Mat1b(10, 10, uchar{0}), kWebpQuality, kWebpMethod),
               std::runtime_error);
  EXPECT_THROW(encodeWebp(photo(20, 20, 7), kWebpQuality, 9), std::runtime_error);
  // A grey "photo": its JPEG is fine, its WebP copy is not; the set says so, from whichever
  // thread encoded it.
  EXPECT_THROW(encodeImageSet({{"overlay", photo(64, 64, 8)}, {"product", cv::Mat1b(32, 32)}}),
               std::runtime_error);
}
