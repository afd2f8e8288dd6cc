#include "garmcap/capture/rig.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <optional>

#include "garmcap/capture/v4l2_decode.h"
#include "garmcap/io/file_io.h"

namespace garmcap::capture {

namespace {

void onlyKeys(const nlohmann::json& j, const std::vector<std::string>& keys,
              const std::string& what) {
  if (!j.is_object())
    throw RigError(what + ": must be a JSON object");
  for (const auto& [k, v] : j.items()) {
    if (std::find(keys.begin(), keys.end(), k) == keys.end()) {
      throw RigError(what + ": unknown field '" + k + "'");
    }
  }
}

std::string sizeText(const cv::Mat& m) {
  return std::to_string(m.cols) + "x" + std::to_string(m.rows);
}

constexpr RigImageFormat kFormats[] = {RigImageFormat::kPng, RigImageFormat::kJpeg};

std::string frameFile(const std::string& frame, RigImageFormat format) {
  return frame + "." + rigImageExtension(format);
}

}  // namespace

const char* rigImageExtension(RigImageFormat format) {
  return format == RigImageFormat::kJpeg ? "jpg" : "png";
}

RigImageFormat parseRigImageFormat(const std::string& text) {
  for (const RigImageFormat f : kFormats) {
    if (text == rigImageExtension(f))
      return f;
  }
  throw std::invalid_argument("image format must be png or jpg, not '" + text + "'");
}

void RigImageOptions::validate() const {
  if (jpegQuality < 1 || jpegQuality > 100) {
    throw std::invalid_argument("JPEG quality must be 1..100, not " + std::to_string(jpegQuality));
  }
}

std::filesystem::path rigFramePath(const std::filesystem::path& caseDir, const std::string& frame) {
  const auto png = caseDir / frameFile(frame, RigImageFormat::kPng);
  const auto jpg = caseDir / frameFile(frame, RigImageFormat::kJpeg);
  std::error_code ec;
  const bool hasPng = std::filesystem::is_regular_file(png, ec);
  const bool hasJpg = std::filesystem::is_regular_file(jpg, ec);
  if (hasPng && hasJpg) {
    throw RigError(png.string() + " and " + jpg.filename().string() +
                   ": both present (a case holds its " + frame +
                   " frame in exactly one of the two formats)");
  }
  if (!hasPng && !hasJpg) {
    throw RigError(png.string() + ": missing (nor is there " + jpg.filename().string() +
                   "; a case holds its " + frame + " frame as one of them)");
  }
  return hasPng ? png : jpg;
}

std::filesystem::path writeRigFrame(const std::filesystem::path& caseDir, const std::string& frame,
                                    const cv::Mat& bgr, const RigImageOptions& options) {
  options.validate();
  const RigImageFormat format = options.format;
  const auto path = caseDir / frameFile(frame, format);
  std::vector<uchar> buf;
  bool ok = false;
  try {
    if (format == RigImageFormat::kJpeg) {
      // Baseline, optimised Huffman tables; OpenCV 4.6 leaves libjpeg's 4:2:0 chroma.
      ok = cv::imencode(
          ".jpg", bgr, buf,
          {cv::IMWRITE_JPEG_QUALITY, options.jpegQuality, cv::IMWRITE_JPEG_OPTIMIZE, 1});
    } else {
      ok = cv::imencode(".png", bgr, buf, {cv::IMWRITE_PNG_COMPRESSION, 9});
    }
  } catch (const cv::Exception& e) {
    throw io::FileError(path.string() + ": encoding failed (" + e.what() + ")");
  }
  if (!ok)
    throw io::FileError(path.string() + ": encoding failed");
  io::writeFileAtomic(path,
                      std::string_view(reinterpret_cast<const char*>(buf.data()), buf.size()));
  for (const RigImageFormat other : kFormats) {
    if (other != format)
      std::filesystem::remove(caseDir / frameFile(frame, other));
  }
  return path;
}

const RigCaseInfo& Rig::find(const std::string& id) const {
  for (const auto& c : cases) {
    if (c.id == id)
      return c;
  }
  throw RigError((dir / "rig.json").string() + ": no case '" + id + "'");
}

Rig readRig(const std::filesystem::path& dir) {
  const auto indexPath = dir / "rig.json";
  const std::string what = indexPath.string();
  Rig rig;
  rig.dir = dir;
  try {
    rig.index = io::readJsonFile(indexPath);
  } catch (const std::exception& e) {
    throw RigError(e.what());
  }
  onlyKeys(rig.index,
           {"format", "version", "generator", "form", "width", "height", "seed", "chart",
            "image_format", "jpeg_quality", "cases"},
           what);
  try {
    if (io::requireString(rig.index, "format", what) != "garmcap-rig") {
      throw RigError(what + ": field 'format' must be \"garmcap-rig\"");
    }
    if (io::requireNumber(rig.index, "version", what) != 1) {
      throw RigError(what + ": field 'version' must be 1");
    }
    std::optional<RigImageFormat> imageFormat;
    if (rig.index.contains("image_format")) {
      const std::string f = io::requireString(rig.index, "image_format", what);
      if (f != "png" && f != "jpg")
        throw RigError(what + ": field 'image_format' must be \"png\" or \"jpg\", not \"" + f +
                       "\"");
      imageFormat = parseRigImageFormat(f);
    }
    if (rig.index.contains("jpeg_quality")) {
      const double q = io::requireNumber(rig.index, "jpeg_quality", what);
      if (!(q >= 1 && q <= 100) || q != std::floor(q))
        throw RigError(what + ": field 'jpeg_quality' must be an integer 1..100");
    }
    const auto& cases = io::requireField(rig.index, "cases", what);
    if (!cases.is_array())
      throw RigError(what + ": field 'cases' must be an array");
    for (std::size_t i = 0; i < cases.size(); ++i) {
      const std::string cw = what + ": cases[" + std::to_string(i) + "]";
      onlyKeys(cases[i], {"id", "dir", "type", "attributes", "hard", "size"}, cw);
      RigCaseInfo c;
      c.id = io::requireString(cases[i], "id", cw);
      c.dir = dir / io::requireString(cases[i], "dir", cw);
      c.type = io::requireString(cases[i], "type", cw);
      const auto& attrs = io::requireField(cases[i], "attributes", cw);
      if (!attrs.is_object())
        throw RigError(cw + ": field 'attributes' must be an object");
      for (const auto& [k, v] : attrs.items()) {
        if (!v.is_string())
          throw RigError(cw + ": attribute '" + k + "' must be a string");
        c.attributes[k] = v.get<std::string>();
      }
      const auto& hard = io::requireField(cases[i], "hard", cw);
      if (!hard.is_boolean())
        throw RigError(cw + ": field 'hard' must be true or false");
      c.hard = hard.get<bool>();
      if (cases[i].contains("size"))
        c.size = io::requireString(cases[i], "size", cw);
      const std::string ofCase = " (case '" + c.id + "' of " + what + ")";
      for (const char* frame : {"empty", "dressed"}) {
        std::filesystem::path file;
        try {
          file = rigFramePath(c.dir, frame);
        } catch (const RigError& e) {
          throw RigError(e.what() + ofCase);
        }
        if (imageFormat && file.extension() != std::string(".") + rigImageExtension(*imageFormat))
          throw RigError(file.string() + ": not " + rigImageExtension(*imageFormat) +
                         " as field 'image_format' of " + what + " says");
      }
      if (!std::filesystem::is_regular_file(c.dir / "truth.json"))
        throw RigError((c.dir / "truth.json").string() + ": missing" + ofCase);
      for (const auto& other : rig.cases) {
        if (other.id == c.id)
          throw RigError(cw + ": duplicate case id '" + c.id + "'");
      }
      rig.cases.push_back(std::move(c));
    }
  } catch (const io::ParseError& e) {
    throw RigError(e.what());
  }
  return rig;
}

EncodedRigImage loadRigImageWithBytes(const std::filesystem::path& file) {
  if (!std::filesystem::is_regular_file(file))
    throw RigError(file.string() + ": missing");
  std::string bytes;
  try {
    bytes = io::readFile(file);
  } catch (const io::FileError& e) {
    throw RigError(e.what());
  }
  const std::string ext = file.extension().string();
  const auto* data = reinterpret_cast<const std::uint8_t*>(bytes.data());
  std::string mediaType;
  if (ext == ".jpg" || ext == ".jpeg") {
    // The framing checks of MJPEG frames: libjpeg would decode a cut file with only a warning.
    switch (checkMjpegFrame({data, bytes.size()})) {
      case MjpegCheck::kOk:
        break;
      case MjpegCheck::kBadEndMarker:
        throw RigError(file.string() + ": truncated JPEG (no FF D9 end marker)");
      case MjpegCheck::kNoStartMarker:
        throw RigError(file.string() + ": not a JPEG (no FF D8 start marker)");
      case MjpegCheck::kTooSmall:
        throw RigError(file.string() + ": not a JPEG (" + std::to_string(bytes.size()) + " bytes)");
    }
    mediaType = "image/jpeg";
  } else if (ext == ".png") {
    static const char kSig[8] = {'\x89', 'P', 'N', 'G', '\r', '\n', '\x1a', '\n'};
    if (bytes.size() < sizeof kSig || !std::equal(kSig, kSig + sizeof kSig, bytes.data()))
      throw RigError(file.string() + ": not a PNG (no PNG signature)");
    mediaType = "image/png";
  }
  cv::Mat img;
  try {
    img = cv::imdecode(cv::Mat(1, static_cast<int>(bytes.size()), CV_8U, bytes.data()),
                       cv::IMREAD_COLOR);
  } catch (const cv::Exception& e) {
    throw RigError(file.string() + ": not a readable image (" + e.what() + ")");
  }
  if (img.empty())
    throw RigError(file.string() + ": not a readable image (corrupt or truncated)");
  return {img, std::move(bytes), std::move(mediaType)};
}

cv::Mat loadRigImage(const std::filesystem::path& file) {
  return loadRigImageWithBytes(file).bgr;
}

RigCase loadRigCase(const std::filesystem::path& caseDir) {
  RigCase c;
  c.dir = caseDir;
  c.id = caseDir.filename().string();
  const auto emptyPath = rigFramePath(caseDir, "empty");
  const auto dressedPath = rigFramePath(caseDir, "dressed");
  c.empty = loadRigImage(emptyPath);
  c.dressed = loadRigImage(dressedPath);
  if (c.empty.size() != c.dressed.size()) {
    throw RigError(dressedPath.string() + ": " + sizeText(c.dressed) + " differs from " +
                   emptyPath.string() + ": " + sizeText(c.empty) +
                   " (the two frames must come from the same camera setting)");
  }
  try {
    c.truth = io::readJsonFile(caseDir / "truth.json");
    if (std::filesystem::is_regular_file(caseDir / "calibration.json")) {
      c.calibration = io::readJsonFile(caseDir / "calibration.json");
    } else if (c.truth.contains("calibration")) {
      c.calibration = c.truth["calibration"];
    }
    // A relative form path in a case's calibration is relative to the case folder, so that a rig
    // can be moved or cloned together with the form it names.
    if (c.calibration.is_object() && c.calibration.contains("form") &&
        c.calibration["form"].is_string()) {
      const std::filesystem::path form = c.calibration["form"].get<std::string>();
      if (form.is_relative())
        c.calibration["form"] = (caseDir / form).lexically_normal().string();
    }
  } catch (const io::ParseError& e) {
    throw RigError(e.what());
  } catch (const io::FileError& e) {
    throw RigError(e.what());
  }
  return c;
}

RigCase cropRigCaseBottom(const RigCase& rigCase, int keepRows) {
  if (keepRows < 1 || keepRows > rigCase.empty.rows)
    throw RigError(rigCase.dir.string() + ": cannot keep " + std::to_string(keepRows) +
                   " rows of a frame " + std::to_string(rigCase.empty.rows) + " rows high");
  RigCase out = rigCase;
  const cv::Rect keep(0, 0, rigCase.empty.cols, keepRows);
  out.empty = rigCase.empty(keep).clone();
  out.dressed = rigCase.dressed(keep).clone();
  const nlohmann::json size = {rigCase.empty.cols, keepRows};
  if (out.calibration.is_object()) {
    out.calibration["image_size"] = size;
    if (!out.calibration.contains("camera") || out.calibration["camera"].is_null()) {
      if (std::filesystem::is_regular_file(rigCase.dir / "camera.json")) {
        try {
          out.calibration["camera"] = io::readJsonFile(rigCase.dir / "camera.json");
        } catch (const io::ParseError& e) {
          throw RigError(e.what());
        } catch (const io::FileError& e) {
          throw RigError(e.what());
        }
      }
    }
    if (out.calibration.contains("camera") && out.calibration["camera"].is_object())
      out.calibration["camera"]["image_size"] = size;
  }
  return out;
}

}  // namespace garmcap::capture
