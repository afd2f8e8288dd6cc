// Product photos before and after issue 17, in one run on the same inputs.
//
//   build/bin/product_photo_bench [--sizes 864x1152,3000x4000] [--reps 3] [--fresh-pages]
//
// For each size a simulated dress scene is rendered and segmented by the pipeline once (its
// silhouette is the mask both methods get). "before" is the method the pipeline used until
// issue 17, kept here as the reference: G <= max(R, B) over the mask dilated by 2 px, a 1.5 px
// Gaussian feather of the binary mask, a square on white scaled down to 1600 px, and both the
// cut-out and the square stored as PNG (compression 1, as the daemon stored every image).
// "after" is pipeline::productPhotos (guided-filter edge, bare-frame cut, chroma despill) with
// the square and the 4:5 crop stored as JPEG (quality 90, as the daemon now does) and the cut-out
// as PNG; from a frame of 2048 px or more the photos are at least 2048 px (as the pipeline asks).
// Freed frame memory stays mapped, as in garmcapd and the CLI (--fresh-pages: returned to the
// kernel, the library's default without keepFrameMemoryMapped, where page faults dominate the
// full-size passes). The first table gives the median wall time of making and of encoding, the
// photo's side and the stored bytes. Wall-clock: compare the rows of one run, not times between
// machines. A second table compares the square photo stored as JPEG (quality 90) and as WebP at
// qualities 80-95 and libwebp methods 1-4 (pipeline::encodeWebp; the station takes 88 at method
// 2, image_files.h): encoding time, bytes, SSIM and PSNR against the lossless photo. A third gives
// the soft shadow's cost (ms the two white photos, unscaled, take with it minus without it) by
// the code before it was made cheaper (kept below as the reference) and by makeProductImages now,
// their ratio (new / old), and the grey levels between the two shadowed squares. A fourth compares
// the PNGs the station stores (the camera frame, the cut-out, the review overlay, the silhouette)
// at level 1 with every row filter, as it stored them until now, against pipeline::encodePng
// (image_files.h): median encoding time, bytes, time ratio.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "garmcap/calib/chroma_key.h"
#include "garmcap/calib/form_model.h"
#include "garmcap/pipeline/capture_pipeline.h"
#include "garmcap/pipeline/image_files.h"
#include "garmcap/pipeline/product_images.h"
#include "garmcap/sim/scene.h"
#include "garmcap/sim/sim.h"

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

std::size_t encoded(const cv::Mat& img, const char* ext, const std::vector<int>& params) {
  std::vector<uchar> buf;
  if (!cv::imencode(ext, img, buf, params))
    throw std::runtime_error(std::string("cannot encode ") + ext);
  return buf.size();
}

// The method before issue 17 (core/garmcap/src/product_images.cpp at the branch point).
struct Before {
  cv::Mat cutout, product;
};

Before before(const cv::Mat3b& cropIn, const cv::Mat1b& mask) {
  cv::Mat3b crop = cropIn.clone();
  cv::Mat1b spill;
  cv::dilate(mask, spill, cv::Mat(), cv::Point(-1, -1), 2);
  garmcap::calib::despill(crop, spill);
  cv::Mat alpha;
  cv::threshold(mask, alpha, 0, 255, cv::THRESH_BINARY);
  cv::GaussianBlur(alpha, alpha, cv::Size(7, 7), 1.5);
  cv::Mat bgra;
  cv::cvtColor(crop, bgra, cv::COLOR_BGR2BGRA);
  std::vector<cv::Mat> ch;
  cv::split(bgra, ch);
  ch[3] = alpha;
  cv::merge(ch, bgra);
  const cv::Rect box = cv::boundingRect(mask);
  const int side = static_cast<int>(std::ceil(std::max(box.width, box.height) / 0.88));
  cv::Mat canvas(side, side, CV_8UC4, cv::Scalar(0, 0, 0, 0));
  bgra(box).copyTo(
      canvas(cv::Rect(cv::Point((side - box.width) / 2, (side - box.height) / 2), box.size())));
  cv::Mat t = canvas;
  if (side > 1600)
    cv::resize(canvas, t, cv::Size(1600, 1600), 0, 0, cv::INTER_AREA);
  cv::Mat3b white(t.size());
  for (int y = 0; y < t.rows; ++y)
    for (int x = 0; x < t.cols; ++x) {
      const cv::Vec4b p = t.at<cv::Vec4b>(y, x);
      for (int c = 0; c < 3; ++c)
        white(y, x)[c] = static_cast<uchar>((p[c] * p[3] + 255 * (255 - p[3]) + 127) / 255);
    }
  return {bgra, white};
}

// The soft shadow as it was made before it was made cheaper (core/garmcap/src/product_images.cpp
// at the branch point of h/ghost17), kept as the reference: the garment's alpha copied into a
// float canvas, the shadow made at reduced resolution from the whole canvas and scaled back up as
// a float image, 255 (1 - shadow) as a float background, then the garment composited over it.
cv::Mat1f oldDropShadow(const cv::Mat1f& canvasAlpha) {
  cv::Mat1f shadow = cv::Mat1f::zeros(canvasAlpha.size());
  const cv::Rect box = cv::boundingRect(canvasAlpha > 0.0f);
  if (box.area() == 0)
    return shadow;
  const double h = box.height;
  const double sigma = std::max(1.0, 0.015 * h);
  const double f = std::max(1.0, sigma / 3.0);
  const cv::Size small(std::max(1, static_cast<int>(std::lround(canvasAlpha.cols / f))),
                       std::max(1, static_cast<int>(std::lround(canvasAlpha.rows / f))));
  cv::Mat1f a;
  cv::resize(canvasAlpha, a, small, 0, 0, cv::INTER_AREA);
  const cv::Mat1b solid = a >= 0.5f;
  cv::Mat1f depth;
  cv::distanceTransform(solid, depth, cv::DIST_L2, cv::DIST_MASK_3);
  const cv::Mat1b core = depth > static_cast<float>(3.5 * 0.015 * h / f);
  const int drop = static_cast<int>(std::lround(4.5 * 0.015 * h / f));
  cv::Mat1f moved = cv::Mat1f::zeros(small);
  if (drop < moved.rows) {
    const cv::Rect from(0, 0, moved.cols, moved.rows - drop);
    core(from).convertTo(moved(from + cv::Point(0, drop)), CV_32F, 0.2 / 255.0);
  }
  cv::Mat1f b;
  cv::GaussianBlur(moved, b, cv::Size(), sigma / f, sigma / f, cv::BORDER_CONSTANT);
  cv::resize(b, shadow, canvasAlpha.size(), 0, 0, cv::INTER_LINEAR);
  return shadow;
}

cv::Mat3b oldOnWhite(const cv::Mat3b& bgr, const cv::Mat1f& alpha, const cv::Rect& box,
                     cv::Size canvas, bool shadow) {
  cv::Mat3b out(canvas, cv::Vec3b(255, 255, 255));
  const cv::Point offset((canvas.width - box.width) / 2, (canvas.height - box.height) / 2);
  cv::Mat1f background;
  if (shadow) {
    cv::Mat1f canvasAlpha = cv::Mat1f::zeros(canvas);
    alpha(box).copyTo(canvasAlpha(cv::Rect(offset, box.size())));
    background = 255.f * (1.f - oldDropShadow(canvasAlpha));
    cv::Mat1b grey;
    background.convertTo(grey, CV_8U);
    cv::cvtColor(grey, out, cv::COLOR_GRAY2BGR);
  }
  for (int y = 0; y < box.height; ++y) {
    const cv::Vec3b* src = bgr.ptr<cv::Vec3b>(box.y + y) + box.x;
    const float* a = alpha.ptr<float>(box.y + y) + box.x;
    const float* bg = background.empty() ? nullptr : background.ptr<float>(offset.y + y) + offset.x;
    cv::Vec3b* dst = out.ptr<cv::Vec3b>(offset.y + y) + offset.x;
    for (int x = 0; x < box.width; ++x) {
      const float al = a[x];
      if (al <= 0.f)
        continue;
      const float under = bg ? bg[x] : 255.f;
      for (int c = 0; c < 3; ++c)
        dst[x][c] = cv::saturate_cast<uchar>(src[x][c] * al + under * (1.f - al));
    }
  }
  return out;
}

// The shadow's cost: the two photos on white (square and 4:5, unscaled) with the shadow and
// without, by the old code above and by pipeline::makeProductImages now, medians of `reps`; and
// how far the new shadowed square is from the old one (grey levels, largest and mean).
void compareShadow(const garmcap::pipeline::ProductLayer& layer, int w, int h, int reps) {
  const cv::Rect box = cv::boundingRect(layer.alpha > 0.0f);
  const int side = static_cast<int>(std::ceil(std::max(box.width, box.height) / 0.88));
  const int ph = static_cast<int>(
      std::ceil(std::max(static_cast<double>(box.height), 1.25 * box.width) / 0.88));
  const cv::Size square(side, side),
      portrait(std::max(box.width, static_cast<int>(std::lround(0.8 * ph))),
               std::max(ph, box.height));
  std::vector<double> oldOff, oldOn, newOff, newOn;
  cv::Mat3b oldSquare, newSquare;
  for (int r = 0; r < reps; ++r) {
    auto t0 = Clock::now();
    oldOnWhite(layer.colour, layer.alpha, box, square, false);
    oldOnWhite(layer.colour, layer.alpha, box, portrait, false);
    oldOff.push_back(msSince(t0));
    t0 = Clock::now();
    oldSquare = oldOnWhite(layer.colour, layer.alpha, box, square, true);
    oldOnWhite(layer.colour, layer.alpha, box, portrait, true);
    oldOn.push_back(msSince(t0));
    garmcap::pipeline::ProductImageOptions o{
        .maxSidePx = 1 << 20, .minSidePx = 0, .marginFraction = 0.06, .pxPerCm = 1};
    // makeProductImages also makes the cut-out: timed without a shadow and with one, the
    // shadow's cost is the difference.
    t0 = Clock::now();
    garmcap::pipeline::makeProductImages(layer.colour, layer.alpha, o);
    newOff.push_back(msSince(t0));
    o.shadow = true;
    t0 = Clock::now();
    newSquare = garmcap::pipeline::makeProductImages(layer.colour, layer.alpha, o).square;
    newOn.push_back(msSince(t0));
  }
  cv::Mat diff;
  cv::absdiff(oldSquare, newSquare, diff);
  double maxDiff = 0;
  cv::minMaxLoc(diff.reshape(1), nullptr, &maxDiff);
  const double oldCost = median(oldOn) - median(oldOff), newCost = median(newOn) - median(newOff);
  std::printf("%4dx%-5d %7d %9.0f %9.0f %9.0f %9.0f %9.0f %9.0f %6.2f %8.0f %8.3f\n", w, h, side,
              median(oldOff), median(oldOn), oldCost, median(newOff), median(newOn), newCost,
              newCost / oldCost, maxDiff, cv::mean(diff)[0]);
}

// Mean SSIM (Wang et al. 2004: 11x11 Gaussian window, sigma 1.5, K1 0.01, K2 0.03) of the
// luma of two 8-bit BGR images of one size.
double ssim(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat x, y;
  cv::cvtColor(a, x, cv::COLOR_BGR2GRAY);
  cv::cvtColor(b, y, cv::COLOR_BGR2GRAY);
  x.convertTo(x, CV_32F);
  y.convertTo(y, CV_32F);
  const double c1 = std::pow(0.01 * 255, 2), c2 = std::pow(0.03 * 255, 2);
  auto blur = [](const cv::Mat& m) {
    cv::Mat out;
    cv::GaussianBlur(m, out, cv::Size(11, 11), 1.5);
    return out;
  };
  const cv::Mat mx = blur(x), my = blur(y);
  const cv::Mat sxx = blur(x.mul(x)) - mx.mul(mx), syy = blur(y.mul(y)) - my.mul(my),
                sxy = blur(x.mul(y)) - mx.mul(my);
  cv::Mat num = (2 * mx.mul(my) + c1).mul(2 * sxy + c2);
  cv::Mat den = (mx.mul(mx) + my.mul(my) + c1).mul(sxx + syy + c2);
  return cv::mean(num / den)[0];
}

// The square photo stored as JPEG (the station's quality 90) and as WebP at several qualities:
// bytes, encoding time and how close the decoded photo stays to the lossless one (SSIM of the
// luma, PSNR of BGR), to pick the WebP quality that looks as good as the JPEG.
void compareFormats(const cv::Mat& photo, int w, int h) {
  struct Format {
    const char* ext;
    int quality;
    int method;  // libwebp's method (image_files.h); OpenCV's encoder always takes 4
  };
  for (const Format f : {Format{".jpg", 90, 0}, Format{".webp", 80, 4}, Format{".webp", 85, 4},
                         Format{".webp", 88, 4}, Format{".webp", 90, 4}, Format{".webp", 95, 4},
                         Format{".webp", 88, 3}, Format{".webp", 88, 2}, Format{".webp", 90, 2},
                         Format{".webp", 92, 2}, Format{".webp", 88, 1}, Format{".webp", 90, 1}}) {
    const bool jpeg = std::string(f.ext) == ".jpg";
    std::vector<uchar> buf;
    const auto t0 = Clock::now();
    if (jpeg) {
      if (!cv::imencode(f.ext, photo, buf,
                        {cv::IMWRITE_JPEG_QUALITY, f.quality, cv::IMWRITE_JPEG_OPTIMIZE, 1}))
        throw std::runtime_error(std::string("cannot encode ") + f.ext);
    } else {
      const std::string bytes = garmcap::pipeline::encodeWebp(photo, f.quality, f.method);
      buf.assign(bytes.begin(), bytes.end());
    }
    const double ms = msSince(t0);
    const cv::Mat back = cv::imdecode(buf, cv::IMREAD_COLOR);
    std::printf("%4dx%-5d %-5s %3d %6d %9.0f %7d %10zu %8.4f %7.2f\n", w, h, f.ext + 1, f.quality,
                f.method, ms, photo.cols, buf.size(), ssim(photo, back), cv::PSNR(photo, back));
  }
}

}  // namespace

// A stored PNG at level 1 with every row filter against pipeline::encodePng, medians of `reps`.
void comparePng(const char* what, const cv::Mat& img, int w, int h, int reps) {
  std::vector<double> old, now;
  std::size_t oldBytes = 0, nowBytes = 0;
  for (int r = 0; r < reps; ++r) {
    auto t0 = Clock::now();
    oldBytes = encoded(img, ".png", {cv::IMWRITE_PNG_COMPRESSION, 1});
    old.push_back(msSince(t0));
    t0 = Clock::now();
    nowBytes = garmcap::pipeline::encodePng(img).size();
    now.push_back(msSince(t0));
  }
  std::printf("%4dx%-5d %-10s %9.0f %9.0f %10zu %10zu %6.2f %6.2f\n", w, h, what, median(old),
              median(now), oldBytes, nowBytes, median(now) / median(old),
              static_cast<double>(nowBytes) / static_cast<double>(oldBytes));
}

int main(int argc, char** argv) {
  using namespace garmcap;
  std::string sizesArg = "864x1152,3000x4000";
  int reps = 3;
  bool freshPages = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--sizes" && i + 1 < argc) {
      sizesArg = argv[++i];
    } else if (a == "--fresh-pages") {
      freshPages = true;
    } else if (a == "--reps" && i + 1 < argc) {
      reps = std::max(1, std::atoi(argv[++i]));
    } else {
      std::fprintf(stderr,
                   "usage: product_photo_bench [--sizes WxH,...] [--reps N] [--fresh-pages]\n");
      return 2;
    }
  }
  if (!freshPages)
    pipeline::keepFrameMemoryMapped();  // as garmcapd and the CLI do
  try {
    const std::string formPath =
        std::string(GARMCAP_SHARED_DIR) + "/data/forms/garmentcode_mean_female/form.json";
    const calib::FormModel form = calib::FormModel::load(formPath);
    std::printf("%-10s %-6s %9s %9s %9s %7s %10s\n", "size", "method", "make_ms", "encode_ms",
                "total_ms", "side", "bytes");
    struct Square {
      int w, h;
      cv::Mat photo;
    };
    std::vector<Square> squares;
    struct StoredPng {
      int w, h;
      const char* what;
      cv::Mat image;
    };
    std::vector<StoredPng> pngs;
    struct Layer {
      int w, h;
      pipeline::ProductLayer layer;
    };
    std::vector<Layer> layers;
    std::stringstream ss(sizesArg);
    std::string item;
    while (std::getline(ss, item, ',')) {
      int w = 0, h = 0;
      if (std::sscanf(item.c_str(), "%dx%d", &w, &h) != 2 || w < 64 || h < 64)
        throw std::invalid_argument("--sizes: '" + item + "' is not WIDTHxHEIGHT");
      sim::RandomSceneOptions o;
      o.size = cv::Size(w, h);
      o.hardFraction = 0;
      o.type = "dress";
      sim::Scene scene = sim::randomScene(form, formPath, 11, o);
      scene.pose.rollRad = 0;  // both methods get the raw frames as the pipeline's upright ones
      const sim::SceneRenderer renderer(form, scene);
      const cv::Mat3b empty = renderer.renderEmpty(), dressed = renderer.renderDressed();
      pipeline::CaptureOptions opt;
      opt.makeProductImages = false;
      opt.makeTexture = false;
      const pipeline::CaptureResult seg =
          pipeline::runCapture(empty, dressed, renderer.calibration(), opt);
      const double s = scene.pose.pxPerCm;
      const int margin = static_cast<int>(std::ceil(2.0 * s));
      cv::Rect box = cv::boundingRect(seg.silhouette);
      box = cv::Rect(box.x - margin, box.y - margin, box.width + 2 * margin,
                     box.height + 2 * margin) &
            cv::Rect(0, 0, w, h);
      const cv::Mat3b crop = dressed(box), bareCrop = empty(box);
      const cv::Mat1b mask = seg.silhouette(box);
      const cv::Vec3b screen = calib::keyGreenScreen(empty, "bare-form frame").screenBgr;

      std::vector<double> bMake, bEnc, aMake, aEnc;
      std::size_t bBytes = 0, aBytes = 0;
      int bSide = 0, aSide = 0;
      cv::Mat lastSquare;
      const std::vector<int> png = {cv::IMWRITE_PNG_COMPRESSION, 1};
      const std::vector<int> jpg = {cv::IMWRITE_JPEG_QUALITY, 90, cv::IMWRITE_JPEG_OPTIMIZE, 1};
      for (int r = 0; r < reps; ++r) {
        auto t0 = Clock::now();
        const Before b = before(crop, mask);
        bMake.push_back(msSince(t0));
        t0 = Clock::now();
        bBytes = encoded(b.cutout, ".png", png) + encoded(b.product, ".png", png);
        bEnc.push_back(msSince(t0));
        bSide = b.product.cols;

        t0 = Clock::now();
        const pipeline::ProductImages a = pipeline::productPhotos(
            crop, mask, bareCrop, screen,
            {.maxSidePx = 4096,
             .minSidePx = std::max(w, h) >= 2048 ? 2048 : 0,  // as the pipeline asks
             .marginFraction = 0.06,
             .pxPerCm = s});
        aMake.push_back(msSince(t0));
        t0 = Clock::now();
        aBytes = encoded(a.cutout, ".png", png) + encoded(a.square, ".jpg", jpg) +
                 encoded(a.portrait, ".jpg", jpg);
        aEnc.push_back(msSince(t0));
        aSide = a.square.cols;
        lastSquare = a.square;
      }
      std::printf("%4dx%-5d %-6s %9.0f %9.0f %9.0f %7d %10zu\n", w, h, "before", median(bMake),
                  median(bEnc), median(bMake) + median(bEnc), bSide, bBytes);
      std::printf("%4dx%-5d %-6s %9.0f %9.0f %9.0f %7d %10zu\n", w, h, "after", median(aMake),
                  median(aEnc), median(aMake) + median(aEnc), aSide, aBytes);
      squares.push_back({w, h, lastSquare});
      layers.push_back(
          {w, h,
           pipeline::productLayer(
               crop, mask, bareCrop, screen,
               {.maxSidePx = 4096, .minSidePx = 0, .marginFraction = 0.06, .pxPerCm = s})});
      const pipeline::CaptureResult full =
          pipeline::runCapture(empty, dressed, renderer.calibration(), pipeline::CaptureOptions{});
      pngs.push_back({w, h, "frame", cv::Mat(dressed)});
      pngs.push_back({w, h, "cutout", full.cutout});
      pngs.push_back({w, h, "overlay", full.overlay});
      pngs.push_back({w, h, "silhouette", full.silhouette});
    }
    std::printf("\n%-10s %-5s %3s %6s %9s %7s %10s %8s %7s\n", "size", "file", "q", "method",
                "encode_ms", "side", "bytes", "ssim", "psnr");
    for (const auto& sq : squares)
      compareFormats(sq.photo, sq.w, sq.h);
    std::printf("\n%-10s %7s %9s %9s %9s %9s %9s %9s %6s %8s %8s\n", "size", "side", "old_off",
                "old_on", "old_cost", "new_off", "new_on", "new_cost", "ratio", "max_diff",
                "mean_diff");
    for (const auto& l : layers)
      compareShadow(l.layer, l.w, l.h, reps);
    std::printf("\n%-10s %-10s %9s %9s %10s %10s %6s %6s\n", "size", "png", "level1_ms", "fast_ms",
                "level1_b", "fast_b", "t", "bytes");
    for (const auto& p : pngs)
      comparePng(p.what, p.image, p.w, p.h, reps);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "product_photo_bench: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
