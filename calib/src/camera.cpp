#include "garmcap/calib/camera.h"

#include <algorithm>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <sstream>

#include "garmcap/calib/errors.h"
#include "garmcap/drafts/file_io.h"

namespace garmcap::calib {

using nlohmann::json;

CameraModel calibrateCamera(const std::vector<cv::Mat>& views, cv::Size inner, double squareMm,
                            std::vector<int>* rejected) {
  if (inner.width < 2 || inner.height < 2 || !(squareMm > 0)) {
    throw CalibError(CalibErrorKind::kCameraCalibration,
                     "camera calibration: the board needs at least 2x2 inner corners and a "
                     "positive square size");
  }
  std::vector<cv::Point3f> board;
  for (int y = 0; y < inner.height; ++y) {
    for (int x = 0; x < inner.width; ++x) {
      board.emplace_back(static_cast<float>(x * squareMm), static_cast<float>(y * squareMm), 0.0f);
    }
  }
  std::vector<std::vector<cv::Point3f>> objectPoints;
  std::vector<std::vector<cv::Point2f>> imagePoints;
  cv::Size size;
  for (std::size_t i = 0; i < views.size(); ++i) {
    cv::Mat grey;
    if (views[i].channels() == 3) {
      cv::cvtColor(views[i], grey, cv::COLOR_BGR2GRAY);
    } else if (views[i].channels() == 4) {
      cv::cvtColor(views[i], grey, cv::COLOR_BGRA2GRAY);
    } else {
      grey = views[i];
    }
    if (size.empty())
      size = grey.size();
    if (grey.size() != size) {
      throw CalibError(
          CalibErrorKind::kCameraCalibration,
          "camera calibration: view " + std::to_string(i) + " differs in size from the first view");
    }
    std::vector<cv::Point2f> corners;
    const bool found = cv::findChessboardCorners(
        grey, inner, corners, cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE);
    if (!found) {
      if (rejected)
        rejected->push_back(static_cast<int>(i));
      continue;
    }
    cv::cornerSubPix(grey, corners, cv::Size(11, 11), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-3));
    imagePoints.push_back(corners);
    objectPoints.push_back(board);
  }
  if (imagePoints.size() < 3) {
    throw CalibError(CalibErrorKind::kCameraCalibration,
                     "camera calibration: the " + std::to_string(inner.width) + "x" +
                         std::to_string(inner.height) + " board was found in " +
                         std::to_string(imagePoints.size()) + " of " +
                         std::to_string(views.size()) +
                         " views; at least 3 are needed (tilt the board differently in each)");
  }
  CameraModel cam;
  cam.imageSize = size;
  cam.boardInnerCorners = inner;
  cam.squareMm = squareMm;
  cam.views = static_cast<int>(imagePoints.size());
  cv::Mat k, dist;
  std::vector<cv::Mat> rvecs, tvecs;
  try {
    cam.rmsPx = cv::calibrateCamera(objectPoints, imagePoints, size, k, dist, rvecs, tvecs);
  } catch (const cv::Exception& e) {
    throw CalibError(CalibErrorKind::kCameraCalibration,
                     std::string("camera calibration: OpenCV failed: ") + e.what());
  }
  cam.cameraMatrix = cv::Matx33d(k);
  dist.reshape(1, 1).copyTo(cam.distortion);
  return cam;
}

CameraModel calibrateCameraFromDirectory(const std::filesystem::path& dir, cv::Size inner,
                                         double squareMm, std::vector<std::string>* rejected) {
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg")
      files.push_back(e.path());
  }
  if (ec)
    throw drafts::FileError(dir.string() + ": cannot list directory: " + ec.message());
  std::sort(files.begin(), files.end());
  std::vector<cv::Mat> views;
  for (const auto& f : files) {
    cv::Mat img = cv::imread(f.string(), cv::IMREAD_GRAYSCALE);
    if (img.empty())
      throw drafts::FileError(f.string() + ": cannot read image");
    views.push_back(img);
  }
  std::vector<int> bad;
  CameraModel cam = calibrateCamera(views, inner, squareMm, &bad);
  if (rejected) {
    for (int i : bad)
      rejected->push_back(files[static_cast<std::size_t>(i)].filename().string());
  }
  return cam;
}

cv::Mat undistortFrame(const cv::Mat& frame, const CameraModel& cam) {
  if (frame.size() != cam.imageSize) {
    std::ostringstream msg;
    msg << "undistort: frame is " << frame.cols << "x" << frame.rows << " but the camera was "
        << "calibrated at " << cam.imageSize.width << "x" << cam.imageSize.height;
    throw std::invalid_argument(msg.str());
  }
  cv::Mat out;
  // Same camera matrix for the output: the undistorted frame is an ideal pinhole image with the
  // calibrated intrinsics, which is what the perspective registration assumes.
  cv::undistort(frame, out, cv::Mat(cam.cameraMatrix), cam.distortion);
  return out;
}

FrameUndistorter::FrameUndistorter(const CameraModel& cam) : size_(cam.imageSize) {
  if (size_.width <= 0 || size_.height <= 0)
    throw std::invalid_argument("undistort: the camera model has no image size");
  cv::initUndistortRectifyMap(cv::Mat(cam.cameraMatrix), cam.distortion, cv::Mat(),
                              cv::Mat(cam.cameraMatrix), size_, CV_16SC2, map1_, map2_);
}

cv::Mat FrameUndistorter::apply(const cv::Mat& frame) const {
  if (frame.size() != size_) {
    std::ostringstream msg;
    msg << "undistort: frame is " << frame.cols << "x" << frame.rows << " but the camera was "
        << "calibrated at " << size_.width << "x" << size_.height;
    throw std::invalid_argument(msg.str());
  }
  cv::Mat out;
  // The few corner pixels that map outside the frame repeat its edge (the screen), so the key
  // finds no foreground there.
  cv::remap(frame, out, map1_, map2_, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return out;
}

std::string cameraToJson(const CameraModel& c) {
  json j;
  j["image_size"] = {c.imageSize.width, c.imageSize.height};
  j["camera_matrix"] = json::array();
  for (int r = 0; r < 3; ++r) {
    j["camera_matrix"].push_back(
        {c.cameraMatrix(r, 0), c.cameraMatrix(r, 1), c.cameraMatrix(r, 2)});
  }
  j["distortion"] = c.distortion;
  j["rms_px"] = c.rmsPx;
  j["views"] = c.views;
  j["board"] = {{"inner_corners", {c.boardInnerCorners.width, c.boardInnerCorners.height}},
                {"square_mm", c.squareMm}};
  return j.dump(2) + "\n";
}

void writeCameraJson(const std::filesystem::path& path, const CameraModel& c) {
  drafts::writeFileAtomic(path, cameraToJson(c));
}

CameraModel cameraFromJson(const json& j, const std::string& what) {
  using drafts::ParseError;
  static const std::set<std::string> kKnown = {"image_size", "camera_matrix", "distortion",
                                               "rms_px",     "views",         "board"};
  if (!j.is_object())
    throw ParseError(what + ": camera model must be a JSON object");
  for (const auto& [k, v] : j.items()) {
    if (!kKnown.count(k))
      throw ParseError(what + ": unknown field '" + k + "'");
  }
  CameraModel c;
  const json& size = drafts::requireField(j, "image_size", what);
  if (!size.is_array() || size.size() != 2 || !size[0].is_number_integer() ||
      !size[1].is_number_integer() || size[0].get<int>() <= 0 || size[1].get<int>() <= 0) {
    throw ParseError(what + ": field 'image_size' must be [width, height] in pixels");
  }
  c.imageSize = {size[0].get<int>(), size[1].get<int>()};
  const json& k = drafts::requireField(j, "camera_matrix", what);
  if (!k.is_array() || k.size() != 3) {
    throw ParseError(what + ": field 'camera_matrix' must be 3 rows of 3 numbers");
  }
  for (int r = 0; r < 3; ++r) {
    const json& row = k[static_cast<std::size_t>(r)];
    if (!row.is_array() || row.size() != 3) {
      throw ParseError(what + ": field 'camera_matrix' must be 3 rows of 3 numbers");
    }
    for (int col = 0; col < 3; ++col) {
      if (!row[static_cast<std::size_t>(col)].is_number()) {
        throw ParseError(what + ": camera_matrix[" + std::to_string(r) + "][" +
                         std::to_string(col) + "] must be a number");
      }
      c.cameraMatrix(r, col) = row[static_cast<std::size_t>(col)].get<double>();
    }
  }
  if (!(c.cameraMatrix(0, 0) > 0) || !(c.cameraMatrix(1, 1) > 0)) {
    throw ParseError(what + ": camera_matrix focal lengths must be positive");
  }
  const json& d = drafts::requireField(j, "distortion", what);
  if (!d.is_array() || (d.size() != 4 && d.size() != 5 && d.size() != 8)) {
    throw ParseError(what + ": field 'distortion' must have 4, 5 or 8 coefficients");
  }
  for (const auto& v : d) {
    if (!v.is_number())
      throw ParseError(what + ": field 'distortion' must hold numbers");
    c.distortion.push_back(v.get<double>());
  }
  c.rmsPx = drafts::requireNumber(j, "rms_px", what);
  c.views = static_cast<int>(drafts::requireNumber(j, "views", what));
  const json& b = drafts::requireField(j, "board", what);
  const json& ic = drafts::requireField(b, "inner_corners", what + ": board");
  if (!ic.is_array() || ic.size() != 2 || !ic[0].is_number_integer() ||
      !ic[1].is_number_integer()) {
    throw ParseError(what + ": board.inner_corners must be [columns, rows]");
  }
  c.boardInnerCorners = {ic[0].get<int>(), ic[1].get<int>()};
  c.squareMm = drafts::requireNumber(b, "square_mm", what + ": board");
  return c;
}

CameraModel readCameraJson(const std::filesystem::path& path) {
  return cameraFromJson(drafts::readJsonFile(path), path.string());
}

}  // namespace garmcap::calib
