#include "garmcap/calib/camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "garmcap/calib/errors.h"

namespace garmcap::calib {
namespace {

namespace fs = std::filesystem;

// A 10x7-square board (9x6 inner corners) drawn at `pxPerMm`, with a white margin.
cv::Mat1b drawBoard(double squareMm, double pxPerMm, double marginMm) {
  const int sq = static_cast<int>(std::lround(squareMm * pxPerMm));
  const int m = static_cast<int>(std::lround(marginMm * pxPerMm));
  cv::Mat1b b(7 * sq + 2 * m, 10 * sq + 2 * m, std::uint8_t{255});
  for (int y = 0; y < 7; ++y) {
    for (int x = 0; x < 10; ++x) {
      if ((x + y) % 2 == 0)
        b(cv::Rect(m + x * sq, m + y * sq, sq, sq)).setTo(0);
    }
  }
  return b;
}

// Views of the board through a pinhole camera K: the homography K [r1 r2 t] S, where S maps board
// pixels to mm with the first inner corner at the origin.
std::vector<cv::Mat> renderViews(const cv::Matx33d& K, cv::Size size, double squareMm) {
  const double pxPerMm = 4.0, marginMm = squareMm;
  const cv::Mat1b board = drawBoard(squareMm, pxPerMm, marginMm);
  const double offset = marginMm + squareMm;  // board px -> mm origin at the first inner corner
  const cv::Matx33d S(1 / pxPerMm, 0, -offset, 0, 1 / pxPerMm, -offset, 0, 0, 1);
  std::vector<cv::Mat> views;
  const double tilts[][3] = {{0.3, 0.1, 0.0},   {-0.3, 0.2, 0.1},  {0.1, -0.35, -0.1},
                             {0.25, 0.3, 0.05}, {-0.2, -0.3, 0.0}, {0.0, 0.4, 0.15},
                             {0.4, 0.0, -0.05}, {-0.1, 0.1, 0.2}};
  for (const auto& t : tilts) {
    cv::Mat R;
    cv::Rodrigues(cv::Vec3d(t[0], t[1], t[2]), R);
    const cv::Matx33d Rm(R);
    const cv::Vec3d tr(-100, -60, 650);  // mm: board about 0.65 m from the camera
    const cv::Matx33d Rt(Rm(0, 0), Rm(0, 1), tr[0], Rm(1, 0), Rm(1, 1), tr[1], Rm(2, 0), Rm(2, 1),
                         tr[2]);
    const cv::Matx33d H = K * Rt * S;
    cv::Mat view;
    cv::warpPerspective(board, view, cv::Mat(H), size, cv::INTER_AREA, cv::BORDER_CONSTANT,
                        cv::Scalar(128));
    views.push_back(view);
  }
  return views;
}

TEST(Camera, RecoversKnownIntrinsicsFromSyntheticChessboards) {
  const cv::Size size(960, 720);
  const cv::Matx33d K(1000, 0, 485, 0, 1000, 355, 0, 0, 1);
  std::vector<int> rejected;
  const CameraModel cam = calibrateCamera(renderViews(K, size, 25.0), {9, 6}, 25.0, &rejected);
  EXPECT_GE(cam.views, 6);
  EXPECT_LT(cam.rmsPx, 0.5);
  EXPECT_NEAR(cam.cameraMatrix(0, 0) / 1000, 1.0, 0.02);
  EXPECT_NEAR(cam.cameraMatrix(1, 1) / 1000, 1.0, 0.02);
  EXPECT_NEAR(cam.cameraMatrix(0, 2), 485, 15);
  EXPECT_NEAR(cam.cameraMatrix(1, 2), 355, 15);
  ASSERT_GE(cam.distortion.size(), 2u);
  EXPECT_LT(std::abs(cam.distortion[0]), 0.1);

  // camera.json round trip.
  const fs::path p =
      fs::temp_directory_path() / ("garmcap_camera_" + std::to_string(::getpid()) + ".json");
  writeCameraJson(p, cam);
  const CameraModel back = readCameraJson(p);
  EXPECT_EQ(back.imageSize, cam.imageSize);
  EXPECT_DOUBLE_EQ(back.cameraMatrix(0, 0), cam.cameraMatrix(0, 0));
  EXPECT_EQ(back.distortion, cam.distortion);
  fs::remove(p);
}

// Largest distance of the bright pixels' per-column centroids from their least-squares line.
double straightnessPx(const cv::Mat1b& img) {
  std::vector<cv::Point2d> pts;
  for (int x = 0; x < img.cols; ++x) {
    double sw = 0, sy = 0;
    for (int y = 0; y < img.rows; ++y)
      sw += img(y, x), sy += y * static_cast<double>(img(y, x));
    if (sw > 200)
      pts.emplace_back(x, sy / sw);
  }
  cv::Vec4d line;
  cv::fitLine(pts, line, cv::DIST_L2, 0, 0.01, 0.01);
  double worst = 0;
  for (const auto& p : pts) {
    worst = std::max(worst, std::abs((p.x - line[2]) * line[1] - (p.y - line[3]) * line[0]));
  }
  return worst;
}

TEST(Camera, UndistortionStraightensALineBentByTheLens) {
  CameraModel cam;
  cam.imageSize = {640, 480};
  cam.cameraMatrix = cv::Matx33d(500, 0, 320, 0, 500, 240, 0, 0, 1);
  cam.distortion = {-0.25, 0.05, 0.0, 0.0, 0.0};
  // A straight 3D line seen through the distorting lens.
  std::vector<cv::Point3d> line3;
  for (double x = -0.55; x <= 0.55; x += 0.001)
    line3.emplace_back(x, 0.33, 1.0);
  std::vector<cv::Point2d> px;
  cv::projectPoints(line3, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cam.cameraMatrix, cam.distortion,
                    px);
  cv::Mat1b img(480, 640, std::uint8_t{0});
  for (const auto& p : px)
    cv::circle(img, cv::Point(cvRound(p.x), cvRound(p.y)), 1, 255, -1);
  const double bent = straightnessPx(img);
  const double straight = straightnessPx(undistortFrame(img, cam));
  EXPECT_GT(bent, 5.0);
  EXPECT_LT(straight, 1.0);
  EXPECT_THROW(undistortFrame(cv::Mat1b(100, 100), cam), std::invalid_argument);
}

// The pipeline's cached undistortion straightens the same bent line and agrees with
// undistortFrame (cv::undistort) to within the fixed-point maps' rounding.
TEST(Camera, CachedUndistortionStraightensTheLineAsUndistortFrameDoes) {
  CameraModel cam;
  cam.imageSize = {640, 480};
  cam.cameraMatrix = cv::Matx33d(500, 0, 320, 0, 500, 240, 0, 0, 1);
  cam.distortion = {-0.25, 0.05, 0.0, 0.0, 0.0};
  std::vector<cv::Point3d> line3;
  for (double x = -0.55; x <= 0.55; x += 0.001)
    line3.emplace_back(x, 0.33, 1.0);
  std::vector<cv::Point2d> px;
  cv::projectPoints(line3, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cam.cameraMatrix, cam.distortion,
                    px);
  cv::Mat1b img(480, 640, std::uint8_t{0});
  for (const auto& p : px)
    cv::circle(img, cv::Point(cvRound(p.x), cvRound(p.y)), 1, 255, -1);
  const FrameUndistorter undistorter(cam);
  const cv::Mat cached = undistorter.apply(img);
  EXPECT_GT(straightnessPx(img), 5.0);
  EXPECT_LT(straightnessPx(cached), 1.0);
  // Away from the corners (where cv::undistort fills black), the two agree pixel by pixel.
  const cv::Rect inner(40, 40, 560, 400);
  cv::Mat diff;
  cv::absdiff(cached(inner), undistortFrame(img, cam)(inner), diff);
  double worst = 0;
  cv::minMaxLoc(diff, nullptr, &worst);
  EXPECT_LE(worst, 8.0);
  EXPECT_LT(cv::mean(diff)[0], 0.2);
  EXPECT_THROW(undistorter.apply(cv::Mat1b(100, 100)), std::invalid_argument);
}

TEST(Camera, TooFewBoardsIsAClearError) {
  std::vector<cv::Mat> blank(4, cv::Mat1b(240, 320, std::uint8_t{200}));
  try {
    calibrateCamera(blank, {9, 6}, 25.0);
    FAIL() << "no exception";
  } catch (const CalibError& e) {
    EXPECT_EQ(e.kind(), CalibErrorKind::kCameraCalibration);
    EXPECT_NE(std::string(e.what()).find("found in 0 of 4"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace garmcap::calib
