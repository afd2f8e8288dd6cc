#include "garmcap/pipeline/grabcut_refine.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <opencv2/imgproc/detail/gcgraph.hpp>
#include <stdexcept>
#include <vector>

namespace garmcap::pipeline {
namespace {

// OpenCV's label enum as plain numbers: comparing cv::Mat with an enum converts it to double,
// which C++20 deprecates.
constexpr int kBgd = cv::GC_BGD;
constexpr int kFgd = cv::GC_FGD;
constexpr int kPrBgd = cv::GC_PR_BGD;
constexpr int kPrFgd = cv::GC_PR_FGD;

void checkInputs(const cv::Mat& bgr, const cv::Mat& trimap) {
  if (bgr.empty() || bgr.type() != CV_8UC3)
    throw std::invalid_argument("grabCut: frame must be a non-empty 8-bit BGR image");
  if (trimap.size() != bgr.size() || trimap.type() != CV_8UC1)
    throw std::invalid_argument("grabCut: trimap must be CV_8UC1 of the frame's size");
  double maxLabel = 0;
  cv::minMaxLoc(trimap, nullptr, &maxLabel);
  if (maxLabel > kPrFgd)
    throw std::invalid_argument(
        "grabCut: trimap holds a value other than GC_BGD/FGD/PR_BGD/PR_FGD");
}

bool hasBothClasses(const cv::Mat& trimap) {
  // GrabCut's k-means needs samples of both classes (CV_Assert in OpenCV's grabcut.cpp).
  const cv::Mat fg = (trimap == kFgd) | (trimap == kPrFgd);
  const int fgCount = cv::countNonZero(fg);
  return fgCount > 0 && fgCount < static_cast<int>(trimap.total());
}

// GrabCut seeds its k-means from OpenCV's thread-local RNG: fix it so a capture gives the same
// silhouette every time, whatever ran before on this thread.
void seedGrabCutRng() {
  cv::theRNG().state = 0x9e3779b97f4a7c15ULL;
}

cv::Mat foreground(const cv::Mat& labels) {
  return ((labels == kFgd) | (labels == kPrFgd));
}

// cv::grabCut's energy constants (imgproc/src/grabcut.cpp): n-link weight gamma, and the hard
// labels' terminal weight 9 gamma, more than the n-links of one pixel can sum to.
constexpr double kGamma = 50.0;
constexpr double kLambda = 9.0 * kGamma;

// One of cv::grabCut's colour models, read from the 1x65 CV_64F matrix it returns: 5 weights,
// then 5 means (BGR), then 5 row-major 3x3 covariances. Evaluates the mixture density as
// cv::grabCut does (without the constant (2 pi)^-3/2, which cancels in the cut).
class FrozenGmm {
 public:
  explicit FrozenGmm(const cv::Mat& model) {
    if (model.type() != CV_64FC1 || model.total() != 65)
      throw std::invalid_argument("grabCut: a colour model must be 1x65 CV_64F");
    const double* m = model.ptr<double>(0);
    for (int k = 0; k < 5; ++k) {
      weight_[k] = m[k];
      mean_[k] = Eigen::Vector3d(m[5 + 3 * k], m[6 + 3 * k], m[7 + 3 * k]);
      const Eigen::Matrix3d cov =
          Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(m + 20 + 9 * k);
      const double det = cov.determinant();
      if (weight_[k] > 0 && !(det > 1e-12))
        throw std::invalid_argument("grabCut: a colour model has a singular covariance");
      scale_[k] = weight_[k] > 0 ? weight_[k] / std::sqrt(det) : 0.0;
      inverse_[k] = weight_[k] > 0 ? Eigen::Matrix3d(cov.inverse()) : Eigen::Matrix3d::Zero();
    }
  }
  double density(const cv::Vec3b& c) const {
    const Eigen::Vector3d colour(c[0], c[1], c[2]);
    double sum = 0;
    for (int k = 0; k < 5; ++k) {
      if (scale_[k] == 0)
        continue;
      const Eigen::Vector3d d = colour - mean_[k];
      sum += scale_[k] * std::exp(-0.5 * d.dot(inverse_[k] * d));
    }
    return sum;
  }

 private:
  std::array<double, 5> weight_{}, scale_{};
  std::array<Eigen::Vector3d, 5> mean_;
  std::array<Eigen::Matrix3d, 5> inverse_;
};

double squaredDistance(const cv::Vec3b& a, const cv::Vec3b& b) {
  const double d0 = a[0] - b[0], d1 = a[1] - b[1], d2 = a[2] - b[2];
  return d0 * d0 + d1 * d1 + d2 * d2;
}

// cv::grabCut's beta, 1 / (2 x the mean squared colour step between 8-neighbours), taken over
// the kContextPx cells the open pixels lie in rather than the whole frame: a frame that is mostly
// flat green screen has a tiny mean step, which makes every colour edge near the garment cheap to
// cut (a 1 MP pants scene lost a 2-3 px strip along its side at the waist, -1.4 cm). Where the
// cells cover the frame this is cv::grabCut's own beta.
constexpr int kContextPx = 256;

double edgeBeta(const cv::Mat3b& bgr, const cv::Mat& open) {
  const int cellsX = (bgr.cols + kContextPx - 1) / kContextPx;
  const int cellsY = (bgr.rows + kContextPx - 1) / kContextPx;
  std::vector<cv::Rect> cells;
  for (int cy = 0; cy < cellsY; ++cy)
    for (int cx = 0; cx < cellsX; ++cx) {
      const cv::Rect cell = cv::Rect(cx * kContextPx, cy * kContextPx, kContextPx, kContextPx) &
                            cv::Rect(0, 0, bgr.cols, bgr.rows);
      if (cv::countNonZero(open(cell)) > 0)
        cells.push_back(cell);
    }
  std::vector<double> sums(cells.size(), 0.0), pairs(cells.size(), 0.0);
  cv::parallel_for_(cv::Range(0, static_cast<int>(cells.size())), [&](const cv::Range& range) {
    for (int i = range.start; i < range.end; ++i) {
      const cv::Rect c = cells[static_cast<std::size_t>(i)];
      double sum = 0, n = 0;
      for (int y = c.y; y < c.y + c.height; ++y) {
        const cv::Vec3b* row = bgr.ptr<cv::Vec3b>(y);
        const cv::Vec3b* up = y > 0 ? bgr.ptr<cv::Vec3b>(y - 1) : nullptr;
        for (int x = c.x; x < c.x + c.width; ++x) {
          if (x > 0) {
            sum += squaredDistance(row[x], row[x - 1]);
            ++n;
          }
          if (up) {
            if (x > 0) {
              sum += squaredDistance(row[x], up[x - 1]);
              ++n;
            }
            sum += squaredDistance(row[x], up[x]);
            ++n;
            if (x < bgr.cols - 1) {
              sum += squaredDistance(row[x], up[x + 1]);
              ++n;
            }
          }
        }
      }
      sums[static_cast<std::size_t>(i)] = sum;
      pairs[static_cast<std::size_t>(i)] = n;
    }
  });
  double total = 0, count = 0;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    total += sums[i];
    count += pairs[i];
  }
  return total <= std::numeric_limits<double>::epsilon() ? 0.0 : 1.0 / (2.0 * total / count);
}

}  // namespace

cv::Mat grabCutFrozen(const cv::Mat& bgrIn, const cv::Mat& labels, const cv::Mat& bgdModel,
                      const cv::Mat& fgdModel) {
  checkInputs(bgrIn, labels);
  const cv::Mat3b bgr = bgrIn;
  const FrozenGmm bgd(bgdModel), fgd(fgdModel);
  const double beta = edgeBeta(bgr, (labels == kPrBgd) | (labels == kPrFgd));
  // Only the open pixels are graph nodes; a hard neighbour's n-link becomes a terminal weight of
  // the node (a GC_FGD neighbour is on the source side for good, so cutting the node from it
  // costs the link if the node goes to the sink, and the other way round for GC_BGD).
  cv::Mat1i node(labels.size(), -1);
  std::vector<cv::Point> open;
  for (int y = 0; y < labels.rows; ++y) {
    const uchar* l = labels.ptr<uchar>(y);
    int* n = node.ptr<int>(y);
    for (int x = 0; x < labels.cols; ++x)
      if (l[x] == kPrBgd || l[x] == kPrFgd) {
        n[x] = static_cast<int>(open.size());
        open.emplace_back(x, y);
      }
  }
  cv::Mat out = labels.clone();
  if (open.empty())
    return out;
  cv::detail::GCGraph<double> graph(static_cast<unsigned>(open.size()),
                                    static_cast<unsigned>(8 * open.size()));
  for (std::size_t i = 0; i < open.size(); ++i)
    graph.addVtx();
  const double diagonal = kGamma / std::sqrt(2.0);
  // The four "backward" neighbours link each pair once, as cv::grabCut does; the forward ones
  // matter only when they are hard.
  constexpr std::array<std::array<int, 2>, 8> kNeighbours = {
      {{-1, 0}, {-1, -1}, {0, -1}, {1, -1}, {1, 0}, {1, 1}, {0, 1}, {-1, 1}}};
  for (std::size_t i = 0; i < open.size(); ++i) {
    const cv::Point p = open[i];
    const cv::Vec3b c = bgr(p);
    double toSource = -std::log(bgd.density(c));
    double toSink = -std::log(fgd.density(c));
    for (std::size_t k = 0; k < kNeighbours.size(); ++k) {
      const cv::Point q(p.x + kNeighbours[k][0], p.y + kNeighbours[k][1]);
      if (q.x < 0 || q.y < 0 || q.x >= bgr.cols || q.y >= bgr.rows)
        continue;
      const double w = (kNeighbours[k][0] != 0 && kNeighbours[k][1] != 0 ? diagonal : kGamma) *
                       std::exp(-beta * squaredDistance(c, bgr(q)));
      const int j = node(q);
      if (j >= 0) {
        if (k < 4)
          graph.addEdges(static_cast<int>(i), j, w, w);
      } else if (labels.at<uchar>(q) == kFgd) {
        toSource += w;
      } else {
        toSink += w;
      }
    }
    graph.addTermWeights(static_cast<int>(i), toSource, toSink);
  }
  graph.maxFlow();
  for (std::size_t i = 0; i < open.size(); ++i)
    out.at<uchar>(open[i]) =
        static_cast<uchar>(graph.inSourceSegment(static_cast<int>(i)) ? kPrFgd : kPrBgd);
  return out;
}

cv::Mat grabCutFullResolution(const cv::Mat& bgr, const cv::Mat& trimap, int iterations) {
  checkInputs(bgr, trimap);
  if (!hasBothClasses(trimap))
    return foreground(trimap);
  cv::Mat labels = trimap.clone();
  cv::Mat bgdModel, fgdModel;
  seedGrabCutRng();
  cv::grabCut(bgr, labels, cv::Rect(), bgdModel, fgdModel, std::max(1, iterations),
              cv::GC_INIT_WITH_MASK);
  return foreground(labels);
}

cv::Mat grabCutCoarseToFine(const cv::Mat& bgr, const cv::Mat& trimap,
                            const CoarseToFineOptions& options) {
  checkInputs(bgr, trimap);
  if (!hasBothClasses(trimap) || cv::countNonZero(trimap >= kPrBgd) == 0)
    return foreground(trimap);  // nothing left to decide

  const double megapixels = static_cast<double>(bgr.total()) / 1e6;
  const double scale = std::min(1.0, std::sqrt(options.workMegapixels / megapixels));
  if (scale > 0.9)
    return grabCutFullResolution(bgr, trimap, options.iterations);

  // 1. Coarse GrabCut: INTER_AREA keeps colours faithful, INTER_NEAREST keeps labels valid.
  cv::Mat smallBgr, smallLabels;
  cv::resize(bgr, smallBgr, cv::Size(), scale, scale, cv::INTER_AREA);
  cv::resize(trimap, smallLabels, smallBgr.size(), 0, 0, cv::INTER_NEAREST);
  cv::Mat bgdModel, fgdModel;
  if (!hasBothClasses(smallLabels))
    return foreground(trimap);
  seedGrabCutRng();
  cv::grabCut(smallBgr, smallLabels, cv::Rect(), bgdModel, fgdModel, options.iterations,
              cv::GC_INIT_WITH_MASK);

  // 2. Upsample the coarse decision; the boundary is uncertain by about one coarse pixel.
  cv::Mat coarseFg;
  cv::resize(foreground(smallLabels), coarseFg, bgr.size(), 0, 0, cv::INTER_LINEAR);
  cv::threshold(coarseFg, coarseFg, 127, 255, cv::THRESH_BINARY);

  // 3. Band around the boundary, wide enough to contain the upsampling error.
  const int halfWidth = std::max(options.minBandPx, static_cast<int>(std::ceil(2.0 / scale)));
  cv::Mat edges;
  cv::morphologyEx(coarseFg, edges, cv::MORPH_GRADIENT,
                   cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
  cv::Mat band;
  cv::dilate(
      edges, band,
      cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * halfWidth + 1, 2 * halfWidth + 1)));

  // Full-resolution labels: hard from the coarse cut outside the band, probable inside it, and
  // the caller's hard labels always win.
  cv::Mat labels(bgr.size(), CV_8UC1, cv::Scalar(kBgd));
  labels.setTo(kFgd, coarseFg);
  cv::Mat bandFg = band & coarseFg;
  cv::Mat bandBg = band & ~coarseFg;
  labels.setTo(kPrFgd, bandFg);
  labels.setTo(kPrBgd, bandBg);
  labels.setTo(kBgd, trimap == kBgd);
  labels.setTo(kFgd, trimap == kFgd);

  // 4. Re-cut the band with the coarse colour models frozen: one graph over the band's open
  // pixels, the same cut whole-frame GrabCut would make there with these models.
  return foreground(grabCutFrozen(bgr, labels, bgdModel, fgdModel));
}

double maskIou(const cv::Mat& a, const cv::Mat& b) {
  CV_Assert(a.size() == b.size());
  const int inter = cv::countNonZero((a != 0) & (b != 0));
  const int uni = cv::countNonZero((a != 0) | (b != 0));
  return uni == 0 ? 1.0 : static_cast<double>(inter) / uni;
}

}  // namespace garmcap::pipeline
