// Calibration subcommands: form (inspect a dress form), make-form (parametric form),
// calibrate (register the form in the bare-form frame), calibrate-camera (chessboards).
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <sstream>
#include <string>

#include "commands.h"
#include "garmcap/calib/camera.h"
#include "garmcap/calib/form_model.h"
#include "garmcap/calib/registration.h"
#include "garmcap/drafts/file_io.h"
#include "garmcap/drafts/measurements.h"
#include "garmcap/drafts/size_charts.h"
#include "garmcap/sim/form_generator.h"

namespace garmcap::cli {

namespace {

namespace fs = std::filesystem;

void printForm(const calib::FormModel& form, bool asJson) {
  if (asJson) {
    std::cout << form.reportJson() << "\n";
    return;
  }
  std::printf("form: %s (%zu vertices, %zu faces, %.2f cm tall)\n",
              form.sidecar().mesh.string().c_str(), form.mesh().vertices.size(),
              form.mesh().faces.size(), form.heightCm());
  std::printf("landmark heights (cm above the floor):\n");
  for (const auto& [name, y] : form.landmarks().toMap()) {
    std::printf("  %-10s %7.2f\n", name.c_str(), y - form.minYCm());
  }
  std::printf("measurements (cm):\n");
  for (const auto& [name, v] : form.measurements().values()) {
    const auto& given = form.sidecar().measurements.values();
    auto it = given.find(name);
    if (it != given.end()) {
      std::printf("  %-22s %7.2f   sidecar %7.2f (%+.2f%%)\n", name.c_str(), v, it->second,
                  (v - it->second) / it->second * 100);
    } else {
      std::printf("  %-22s %7.2f\n", name.c_str(), v);
    }
  }
}

cv::Size parseBoard(const std::string& text) {
  int w = 0, h = 0;
  char x = 0;
  std::istringstream in(text);
  if (!(in >> w >> x >> h) || (x != 'x' && x != 'X') || w < 2 || h < 2) {
    throw std::invalid_argument("--board must be COLSxROWS of inner corners, e.g. 9x6; got '" +
                                text + "'");
  }
  return {w, h};
}

}  // namespace

void addCalibCommands(CLI::App& app) {
  // garmcap form --form F [--json]
  {
    auto* cmd = app.add_subcommand("form",
                                   "Inspect a dress form: landmark heights and measurements "
                                   "derived from its mesh, compared with its sidecar");
    auto form = std::make_shared<std::string>();
    auto json = std::make_shared<bool>(false);
    cmd->add_option("--form", *form, "Form sidecar (.json) or mesh (.obj/.ply)")->required();
    cmd->add_flag("--json", *json, "Print the report as JSON");
    cmd->callback([form, json] { printForm(calib::FormModel::load(*form), *json); });
  }
  // garmcap make-form (--measurements M.json | --chart C --size S) --out F.obj
  {
    auto* cmd = app.add_subcommand(
        "make-form", "Generate a parametric dress form (mesh + sidecar) from body measurements");
    auto measurements = std::make_shared<std::string>();
    auto chart = std::make_shared<std::string>();
    auto size = std::make_shared<std::string>();
    auto out = std::make_shared<std::string>();
    auto step = std::make_shared<double>(1.0);
    auto segments = std::make_shared<int>(64);
    auto torso = std::make_shared<bool>(false);
    cmd->add_option("--measurements", *measurements, "Measurements JSON or .vit");
    cmd->add_option("--chart", *chart, "Size chart name (e.g. korean_women)");
    cmd->add_option("--size", *size, "Size in the chart (e.g. 55)");
    cmd->add_option("--out", *out, "Output mesh (.obj); the sidecar is written beside it (.json)")
        ->required();
    cmd->add_option("--ring-step", *step, "Vertical spacing of torso rings in cm")
        ->check(CLI::Range(0.2, 5.0));
    cmd->add_option("--segments", *segments, "Vertices per torso ring")->check(CLI::Range(16, 256));
    cmd->add_flag("--torso", *torso,
                  "A torso dress form on a pole (neck cap, no head, arms or legs) instead of a "
                  "full mannequin");
    cmd->callback([=] {
      drafts::Measurements body;
      if (!measurements->empty()) {
        body = drafts::readMeasurementsFile(*measurements);
      } else if (!chart->empty() && !size->empty()) {
        body = drafts::sizeChart(*chart).body(*size);
      } else {
        throw std::invalid_argument("make-form: give --measurements or --chart and --size");
      }
      const sim::ParametricForm pf(body,
                                   *torso ? sim::FormKind::kTorso : sim::FormKind::kMannequin);
      const fs::path meshPath(*out);
      fs::path sidecarPath = meshPath;
      sidecarPath.replace_extension(".json");
      calib::FormSidecar sidecar = pf.sidecar(meshPath.filename().string());
      sidecar.name = (!chart->empty() ? *chart + " size " + *size : std::string("parametric")) +
                     (*torso ? " torso form" : " form");
      calib::writeObj(meshPath, pf.mesh(*step, *segments),
                      "garmcap parametric dress form, cm, y up, facing +z; sidecar " +
                          sidecarPath.filename().string());
      calib::writeFormSidecar(sidecarPath, sidecar);
      // Check what was written the way every consumer will read it.
      const auto form = calib::FormModel::load(sidecarPath);
      std::printf("wrote %s and %s\n", meshPath.string().c_str(), sidecarPath.string().c_str());
      printForm(form, false);
    });
  }
  // garmcap calibrate --form F --empty E.png [--camera camera.json] [--distance-cm D] --out C
  {
    auto* cmd = app.add_subcommand(
        "calibrate",
        "Register the dress form in the bare-form frame: px/cm, fit IoU, landmarks; "
        "writes the calibration JSON and a debug overlay PNG beside it");
    auto form = std::make_shared<std::string>();
    auto empty = std::make_shared<std::string>();
    auto camera = std::make_shared<std::string>();
    auto distance = std::make_shared<double>(0.0);
    auto out = std::make_shared<std::string>();
    cmd->add_option("--form", *form, "Form sidecar (.json) or mesh (.obj/.ply)")->required();
    cmd->add_option("--empty", *empty, "Frame of the bare form on the green screen")->required();
    cmd->add_option("--camera", *camera,
                    "camera.json from calibrate-camera (undistorts the frame)");
    cmd->add_option("--distance-cm", *distance,
                    "Camera to form-axis distance in cm; with --camera, fit in full perspective");
    cmd->add_option("--out", *out, "Calibration JSON to write")->required();
    cmd->callback([=] {
      const fs::path sidecarPath = calib::resolveFormSidecar(*form);
      const auto model = calib::FormModel::load(sidecarPath);
      cv::Mat frame = readFrameFile(*empty, "bare-form frame");
      std::optional<calib::CameraModel> cam;
      calib::RegistrationOptions options;
      if (!camera->empty()) {
        cam = calib::readCameraJson(*camera);
        frame = calib::undistortFrame(frame, *cam);
        options.intrinsics = cam->intrinsics();
        if (*distance > 0)
          options.distanceCm = *distance;
      } else if (*distance > 0) {
        throw std::invalid_argument("calibrate: --distance-cm needs --camera (intrinsics)");
      }
      const calib::Registration reg = calib::registerForm(model, frame, *empty, options);
      const calib::Calibration c =
          calib::makeCalibration(model, reg, fs::absolute(sidecarPath), fs::absolute(*empty), cam);
      const fs::path outPath(*out);
      calib::writeCalibration(outPath, c);
      fs::path overlayPath = outPath;
      overlayPath.replace_extension(".overlay.png");
      if (!cv::imwrite(overlayPath.string(), calib::drawOverlay(frame, reg))) {
        throw drafts::FileError(overlayPath.string() + ": cannot write overlay");
      }
      std::printf("scale: %.4f px/cm (%s)\n", reg.pose.pxPerCm,
                  reg.pose.perspective ? "perspective" : "orthographic");
      if (auto d = reg.pose.distanceCm())
        std::printf("distance: %.1f cm\n", *d);
      std::printf("offset: %.2f %.2f px, roll %.3f deg\n", reg.pose.offsetPx.x(),
                  reg.pose.offsetPx.y(), reg.pose.rollRad * 180 / 3.14159265358979);
      std::printf("IoU: %.4f (%d iterations)\n", reg.iou, reg.iterations);
      std::printf("landmarks (px):\n");
      for (const auto& [name, p] : reg.landmarks) {
        std::printf("  %-16s %8.2f %8.2f\n", name.c_str(), p.x(), p.y());
      }
      std::printf("wrote %s and %s\n", outPath.string().c_str(), overlayPath.string().c_str());
    });
  }
  // garmcap calibrate-camera --images DIR --board 9x6 --square-mm 25 --out camera.json
  {
    auto* cmd = app.add_subcommand("calibrate-camera",
                                   "Camera intrinsics and distortion from chessboard images");
    auto images = std::make_shared<std::string>();
    auto board = std::make_shared<std::string>("9x6");
    auto square = std::make_shared<double>(25.0);
    auto out = std::make_shared<std::string>();
    cmd->add_option("--images", *images, "Folder of chessboard images (.png/.jpg)")->required();
    cmd->add_option("--board", *board, "Inner corners COLSxROWS")->capture_default_str();
    cmd->add_option("--square-mm", *square, "Square size in mm")->capture_default_str();
    cmd->add_option("--out", *out, "camera.json to write")->required();
    cmd->callback([=] {
      std::vector<std::string> rejected;
      const auto cam =
          calib::calibrateCameraFromDirectory(*images, parseBoard(*board), *square, &rejected);
      calib::writeCameraJson(*out, cam);
      std::printf("views used: %d, rejected: %zu", cam.views, rejected.size());
      for (const auto& r : rejected)
        std::printf(" %s", r.c_str());
      std::printf("\nreprojection RMS: %.3f px\n", cam.rmsPx);
      std::printf("fx %.2f fy %.2f cx %.2f cy %.2f\n", cam.cameraMatrix(0, 0),
                  cam.cameraMatrix(1, 1), cam.cameraMatrix(0, 2), cam.cameraMatrix(1, 2));
      std::printf("wrote %s\n", out->c_str());
    });
  }
}

}  // namespace garmcap::cli
