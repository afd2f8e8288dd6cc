#include "garmcap/pipeline/texture.h"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace garmcap::pipeline {
namespace {

constexpr int kMaxPatchPx = 512;  // texture analysis never needs more detail than this

// Local maxima of a 1-D profile above `threshold`, at least `minGap` apart (strongest first).
std::vector<int> findPeaks(const std::vector<double>& profile, double threshold, int minGap) {
  std::vector<int> candidates;
  for (int i = 1; i + 1 < static_cast<int>(profile.size()); ++i) {
    const double v = profile[static_cast<std::size_t>(i)];
    if (v >= threshold && v >= profile[static_cast<std::size_t>(i - 1)] &&
        v > profile[static_cast<std::size_t>(i + 1)])
      candidates.push_back(i);
  }
  std::sort(candidates.begin(), candidates.end(), [&](int a, int b) {
    return profile[static_cast<std::size_t>(a)] > profile[static_cast<std::size_t>(b)];
  });
  std::vector<int> peaks;
  for (int c : candidates) {
    const bool farEnough =
        std::all_of(peaks.begin(), peaks.end(), [&](int p) { return std::abs(p - c) >= minGap; });
    if (farEnough)
      peaks.push_back(c);
  }
  std::sort(peaks.begin(), peaks.end());
  return peaks;
}

double median(std::vector<double> v) {
  if (v.empty())
    return 0;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// Sub-pixel refinement of a peak by a parabola through its neighbours.
double refinePeak(const std::vector<double>& p, int i) {
  if (i <= 0 || i + 1 >= static_cast<int>(p.size()))
    return i;
  const double a = p[static_cast<std::size_t>(i - 1)], b = p[static_cast<std::size_t>(i)],
               c = p[static_cast<std::size_t>(i + 1)];
  const double denom = a - 2 * b + c;
  return std::abs(denom) < 1e-12 ? i : i + 0.5 * (a - c) / denom;
}

// Period of a 1-D profile by normalised autocorrelation; 0 when it is not periodic.
double profilePeriod(const std::vector<double>& profile, double minCorrelation) {
  const int n = static_cast<int>(profile.size());
  if (n < 16)
    return 0;
  const double mean = std::accumulate(profile.begin(), profile.end(), 0.0) / n;
  std::vector<double> d(profile.size());
  for (int i = 0; i < n; ++i)
    d[static_cast<std::size_t>(i)] = profile[static_cast<std::size_t>(i)] - mean;
  double var = 0;
  for (double x : d)
    var += x * x;
  if (var < 1e-9 * n)
    return 0;
  std::vector<double> ac(static_cast<std::size_t>(n / 2), 0.0);
  for (int lag = 0; lag < n / 2; ++lag) {
    double s = 0;
    for (int i = 0; i + lag < n; ++i)
      s += d[static_cast<std::size_t>(i)] * d[static_cast<std::size_t>(i + lag)];
    ac[static_cast<std::size_t>(lag)] = s / var * n / (n - lag);
  }
  // First lag after the central lobe falls below zero whose autocorrelation is a strong peak.
  int lag = 1;
  while (lag < n / 2 && ac[static_cast<std::size_t>(lag)] > 0)
    ++lag;
  int best = -1;
  for (int i = lag; i + 1 < n / 2; ++i) {
    if (ac[static_cast<std::size_t>(i)] >= ac[static_cast<std::size_t>(i - 1)] &&
        ac[static_cast<std::size_t>(i)] > ac[static_cast<std::size_t>(i + 1)] &&
        ac[static_cast<std::size_t>(i)] > minCorrelation) {
      best = i;
      break;
    }
  }
  return best < 0 ? 0 : refinePeak(ac, best);
}

std::vector<double> rowMeans(const cv::Mat& grey) {
  cv::Mat m;
  cv::reduce(grey, m, 1, cv::REDUCE_AVG, CV_64F);
  return std::vector<double>(m.begin<double>(), m.end<double>());
}

// Largest axis-aligned square inside the mask, around its most interior point.
cv::Rect interiorSquare(const cv::Mat& mask) {
  cv::Mat dist;
  cv::distanceTransform(mask != 0, dist, cv::DIST_L2, 5);
  double maxDist = 0;
  cv::Point centre;
  cv::minMaxLoc(dist, nullptr, &maxDist, nullptr, &centre);
  const int half = static_cast<int>(maxDist / std::sqrt(2.0)) - 1;
  if (half < 8)
    return {};
  return cv::Rect(centre.x - half, centre.y - half, 2 * half, 2 * half) &
         cv::Rect(0, 0, mask.cols, mask.rows);
}

}  // namespace

TracedLines traceHorizontalLines(const cv::Mat& grey, int stripWidthPx) {
  TracedLines out;
  const int strips = grey.cols / stripWidthPx;
  if (strips < 4 || grey.rows < 16)
    return out;
  cv::Mat gy;
  cv::Sobel(grey, gy, CV_32F, 0, 1, 3);
  gy = cv::abs(gy);
  // Per strip, the mean edge strength along y.
  std::vector<std::vector<double>> profile(static_cast<std::size_t>(strips));
  for (int s = 0; s < strips; ++s) {
    cv::Mat col;
    cv::reduce(gy.colRange(s * stripWidthPx, (s + 1) * stripWidthPx), col, 1, cv::REDUCE_AVG,
               CV_64F);
    profile[static_cast<std::size_t>(s)].assign(col.begin<double>(), col.end<double>());
    out.stripX.push_back((s + 0.5) * stripWidthPx);
  }
  const int s0 = strips / 2;
  const auto& centre = profile[static_cast<std::size_t>(s0)];
  const double maxEdge = *std::max_element(centre.begin(), centre.end());
  const double floorEdge = median(centre);
  // A line is an edge well above the fabric's own texture noise.
  const double threshold = std::max(0.3 * maxEdge, 3.0 * floorEdge);
  if (maxEdge < 8.0)
    return out;  // too little contrast to be a printed line
  const auto seeds = findPeaks(centre, threshold, 4);
  const int reach = std::max(2, stripWidthPx / 3);  // how far a line may climb between strips

  for (int seed : seeds) {
    std::vector<double> ys(static_cast<std::size_t>(strips), -1.0);
    ys[static_cast<std::size_t>(s0)] = refinePeak(centre, seed);
    const double seedStrength = centre[static_cast<std::size_t>(seed)];
    bool complete = true;
    for (int dir : {+1, -1}) {
      int y = seed;
      for (int s = s0 + dir; s >= 0 && s < strips; s += dir) {
        const auto& p = profile[static_cast<std::size_t>(s)];
        int best = -1;
        double bestV = 0;
        for (int yy = std::max(1, y - reach); yy <= std::min(grey.rows - 2, y + reach); ++yy) {
          if (p[static_cast<std::size_t>(yy)] > bestV) {
            bestV = p[static_cast<std::size_t>(yy)];
            best = yy;
          }
        }
        if (best < 0 || bestV < 0.35 * seedStrength) {
          complete = false;
          break;
        }
        y = best;
        ys[static_cast<std::size_t>(s)] = refinePeak(p, best);
      }
    }
    if (complete)
      out.lineY.push_back(std::move(ys));
  }
  // Lines must keep their order at every strip (crossing lines are mis-traces): keep a maximal
  // run of lines that stay strictly ordered and at least 2 px apart.
  std::vector<std::vector<double>> ordered;
  for (auto& line : out.lineY) {
    if (ordered.empty()) {
      ordered.push_back(std::move(line));
      continue;
    }
    bool ok = true;
    for (std::size_t s = 0; s < line.size(); ++s)
      ok = ok && line[s] > ordered.back()[s] + 2.0;
    if (ok)
      ordered.push_back(std::move(line));
  }
  out.lineY = ordered.size() >= 3 ? std::move(ordered) : std::vector<std::vector<double>>{};
  return out;
}

std::optional<cv::Mat> straightenHorizontal(const cv::Mat& bgr, const TracedLines& lines) {
  const int nLines = static_cast<int>(lines.lineY.size());
  const int nStrips = static_cast<int>(lines.stripX.size());
  if (nLines < 3 || nStrips < 2)
    return std::nullopt;
  auto photo = [&](int l, int s) {
    return Eigen::Vector2d(lines.stripX[static_cast<std::size_t>(s)],
                           lines.lineY[static_cast<std::size_t>(l)][static_cast<std::size_t>(s)]);
  };
  // Triangles of the quad mesh (line l..l+1, strip s..s+1), as (line, strip) vertex pairs.
  struct Tri {
    std::array<std::pair<int, int>, 3> v;
  };
  std::vector<Tri> tris;
  for (int l = 0; l + 1 < nLines; ++l)
    for (int s = 0; s + 1 < nStrips; ++s) {
      tris.push_back({{{{l, s}, {l, s + 1}, {l + 1, s}}}});
      tris.push_back({{{{l, s + 1}, {l + 1, s + 1}, {l + 1, s}}}});
    }
  // The y-row of each triangle's deformation gradient as a linear form in the line unknowns
  // (every vertex of line l shares unknown y_l: the line constraints, by variable merging).
  // The x-row is decoupled and the identity already minimises it (zero energy), so x stays.
  const int nT = static_cast<int>(tris.size());
  std::vector<std::array<Eigen::VectorXd, 2>> grad(static_cast<std::size_t>(nT));
  for (int i = 0; i < nT; ++i) {
    const auto& t = tris[static_cast<std::size_t>(i)];
    const Eigen::Vector2d a = photo(t.v[0].first, t.v[0].second);
    const Eigen::Vector2d b = photo(t.v[1].first, t.v[1].second);
    const Eigen::Vector2d c = photo(t.v[2].first, t.v[2].second);
    Eigen::Matrix2d V;
    V.col(0) = b - a;
    V.col(1) = c - a;
    if (std::abs(V.determinant()) < 1e-6)
      return std::nullopt;
    const Eigen::Matrix2d Vinv = V.inverse();
    for (int k = 0; k < 2; ++k) {
      Eigen::VectorXd g = Eigen::VectorXd::Zero(nLines);
      g(t.v[0].first) += -(Vinv(0, k) + Vinv(1, k));
      g(t.v[1].first) += Vinv(0, k);
      g(t.v[2].first) += Vinv(1, k);
      grad[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)] = g;
    }
  }
  // Least squares: sqrt(wS)(G_i - G_j) = 0 for neighbours, sqrt(wI) G_i = e_y.
  const double wS = 1.0, wI = 0.001;
  Eigen::MatrixXd AtA = Eigen::MatrixXd::Zero(nLines, nLines);
  Eigen::VectorXd Atb = Eigen::VectorXd::Zero(nLines);
  auto addRow = [&](const Eigen::VectorXd& row, double rhs, double w) {
    AtA.noalias() += w * row * row.transpose();
    Atb.noalias() += w * rhs * row;
  };
  auto gradOf = [&](int i, int k) -> const Eigen::VectorXd& {
    return grad[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)];
  };
  for (int i = 0; i < nT; ++i)
    for (int k = 0; k < 2; ++k)
      addRow(gradOf(i, k), k == 1 ? 1.0 : 0.0, wI);
  // Pairs of triangles that share an edge: the quad's two halves (diagonal), the right half of
  // a quad with the left half of the next quad along the line (vertical edge), and the right
  // half with the left half of the quad below (the lower line's edge).
  const int quadsPerRow = nStrips - 1;
  auto tri = [&](int l, int s, int half) { return 2 * (l * quadsPerRow + s) + half; };
  auto addSmooth = [&](int i, int j) {
    for (int k = 0; k < 2; ++k)
      addRow(gradOf(i, k) - gradOf(j, k), 0.0, wS);
  };
  for (int l = 0; l + 1 < nLines; ++l)
    for (int s = 0; s < quadsPerRow; ++s) {
      addSmooth(tri(l, s, 0), tri(l, s, 1));
      if (s + 1 < quadsPerRow)
        addSmooth(tri(l, s, 1), tri(l, s + 1, 0));
      if (l + 2 < nLines)
        addSmooth(tri(l, s, 1), tri(l + 1, s, 0));
    }
  // Pin the first and last line at their mean photo y: without two anchors the smoothness term
  // shrinks the grid (research §5, pitfall 1).
  auto meanY = [&](int l) {
    const auto& ys = lines.lineY[static_cast<std::size_t>(l)];
    return std::accumulate(ys.begin(), ys.end(), 0.0) / static_cast<double>(ys.size());
  };
  std::vector<int> freeIdx;
  for (int l = 1; l + 1 < nLines; ++l)
    freeIdx.push_back(l);
  Eigen::VectorXd y(nLines);
  y(0) = meanY(0);
  y(nLines - 1) = meanY(nLines - 1);
  if (!freeIdx.empty()) {
    const int m = static_cast<int>(freeIdx.size());
    Eigen::SparseMatrix<double> K(m, m);
    std::vector<Eigen::Triplet<double>> trips;
    Eigen::VectorXd rhs(m);
    for (int r = 0; r < m; ++r) {
      const int lr = freeIdx[static_cast<std::size_t>(r)];
      rhs(r) = Atb(lr) - AtA(lr, 0) * y(0) - AtA(lr, nLines - 1) * y(nLines - 1);
      for (int c = 0; c < m; ++c) {
        const double v = AtA(lr, freeIdx[static_cast<std::size_t>(c)]);
        if (v != 0)
          trips.emplace_back(r, c, v);
      }
    }
    K.setFromTriplets(trips.begin(), trips.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(K);
    if (solver.info() != Eigen::Success)
      return std::nullopt;
    const Eigen::VectorXd sol = solver.solve(rhs);
    if (solver.info() != Eigen::Success || !sol.allFinite())
      return std::nullopt;
    for (int r = 0; r < m; ++r)
      y(freeIdx[static_cast<std::size_t>(r)]) = sol(r);
  }
  for (int l = 0; l + 1 < nLines; ++l)
    if (!(y(l + 1) > y(l) + 0.5))
      return std::nullopt;  // the solve folded the mesh

  // Dense inverse map: every output pixel lies in one straightened triangle; its source is the
  // same barycentric combination of the photo triangle (the piecewise-affine deformation).
  const double x0 = lines.stripX.front(), x1 = lines.stripX.back();
  const int outW = static_cast<int>(std::floor(x1 - x0));
  const int outH = static_cast<int>(std::floor(y(nLines - 1) - y(0)));
  if (outW < 4 || outH < 4)
    return std::nullopt;
  cv::Mat mapX(outH, outW, CV_32F), mapY(outH, outW, CV_32F);
  const double dx = lines.stripX[1] - lines.stripX[0];
  int l = 0;
  for (int r = 0; r < outH; ++r) {
    const double yy = y(0) + r + 0.5;
    while (l + 2 < nLines && yy > y(l + 1))
      ++l;
    const double v = std::clamp((yy - y(l)) / (y(l + 1) - y(l)), 0.0, 1.0);
    for (int c = 0; c < outW; ++c) {
      const double xx = x0 + c + 0.5;
      const int s = std::clamp(static_cast<int>((xx - x0) / dx), 0, nStrips - 2);
      const double u = std::clamp((xx - lines.stripX[static_cast<std::size_t>(s)]) / dx, 0.0, 1.0);
      const Eigen::Vector2d p00 = photo(l, s), p01 = photo(l, s + 1), p10 = photo(l + 1, s),
                            p11 = photo(l + 1, s + 1);
      const Eigen::Vector2d src =
          (u + v <= 1.0) ? Eigen::Vector2d(p00 + u * (p01 - p00) + v * (p10 - p00))
                         : Eigen::Vector2d(p11 + (1 - u) * (p10 - p11) + (1 - v) * (p01 - p11));
      mapX.at<float>(r, c) = static_cast<float>(src.x());
      mapY.at<float>(r, c) = static_cast<float>(src.y());
    }
  }
  cv::Mat out;
  cv::remap(bgr, out, mapX, mapY, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return out;
}

TextureResult extractTexture(const cv::Mat& bgr, const cv::Mat& mask) {
  if (bgr.empty() || bgr.type() != CV_8UC3 || mask.size() != bgr.size())
    throw std::invalid_argument("texture: need an 8-bit BGR frame and a mask of its size");
  if (cv::countNonZero(mask) == 0)
    throw std::invalid_argument("texture: the garment mask is empty");

  TextureResult result;
  // Median colour over the whole garment: robust to shading folds and prints.
  {
    std::vector<cv::Mat> ch;
    cv::split(bgr, ch);
    for (int k = 0; k < 3; ++k) {
      std::vector<double> values;
      for (int r = 0; r < bgr.rows; r += 2)
        for (int c = 0; c < bgr.cols; c += 2)
          if (mask.at<uchar>(r, c))
            values.push_back(ch[static_cast<std::size_t>(k)].at<uchar>(r, c));
      result.meanColour[k] = static_cast<uchar>(median(values));
    }
  }
  result.tile =
      cv::Mat(64, 64, CV_8UC3,
              cv::Scalar(result.meanColour[0], result.meanColour[1], result.meanColour[2]));

  cv::Rect square = interiorSquare(mask);
  if (square.area() == 0)
    return result;
  cv::Mat patch = bgr(square).clone();
  if (patch.cols > kMaxPatchPx)
    cv::resize(patch, patch, cv::Size(kMaxPatchPx, kMaxPatchPx), 0, 0, cv::INTER_AREA);

  auto greyOf = [](const cv::Mat& img) {
    cv::Mat g;
    cv::cvtColor(img, g, cv::COLOR_BGR2GRAY);
    g.convertTo(g, CV_32F);
    cv::GaussianBlur(g, g, cv::Size(3, 3), 0);
    return g;
  };

  // Horizontal lines first, then vertical ones by the same routine on the transposed image.
  cv::Mat straight = patch;
  const TracedLines h = traceHorizontalLines(greyOf(straight));
  result.horizontalLines = static_cast<int>(h.lineY.size());
  if (auto s = straightenHorizontal(straight, h))
    straight = *s;
  cv::Mat transposed = straight.t();
  const TracedLines v = traceHorizontalLines(greyOf(transposed));
  result.verticalLines = static_cast<int>(v.lineY.size());
  if (auto s = straightenHorizontal(transposed, v))
    straight = s->t();

  const cv::Mat g = greyOf(straight);
  const double periodY = result.horizontalLines >= 3 ? profilePeriod(rowMeans(g), 0.4) : 0;
  const double periodX =
      result.verticalLines >= 3 ? profilePeriod(rowMeans(cv::Mat(g.t())), 0.4) : 0;
  result.periodYPx = periodY;
  result.periodXPx = periodX;
  if (periodY <= 0 && periodX <= 0)
    return result;  // solid (or a print we do not straighten)

  result.kind = (periodY > 0 && periodX > 0) ? FabricKind::kChecks : FabricKind::kStripes;
  // One repeat from the middle of the straightened patch, where the straightening is best.
  const int th = periodY > 0 ? static_cast<int>(std::lround(periodY)) : std::min(straight.rows, 64);
  const int tw = periodX > 0 ? static_cast<int>(std::lround(periodX)) : std::min(straight.cols, 64);
  const cv::Rect tile((straight.cols - tw) / 2, (straight.rows - th) / 2, tw, th);
  result.tile = straight(tile & cv::Rect(0, 0, straight.cols, straight.rows)).clone();
  return result;
}

}  // namespace garmcap::pipeline
