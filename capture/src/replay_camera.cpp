#include "garmcap/capture/replay_camera.h"

#include <algorithm>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "garmcap/capture/rig.h"

namespace garmcap::capture {
namespace fs = std::filesystem;

namespace {

const char* frameName(Shot shot) {
  return shot == Shot::kDressed ? "dressed" : "empty";
}

/// The file of one frame of a case (PNG or JPEG, exactly one: rigFramePath); the error names
/// the case and the files.
fs::path framePath(const fs::path& caseDir, Shot shot, const std::string& caseId) {
  try {
    return rigFramePath(caseDir, frameName(shot));
  } catch (const RigError& e) {
    throw CameraError(CameraErrorKind::kBadData, "rig case " + caseId + ": " + e.what());
  }
}

/// Reads an image file with the rig reader's checks; the error names the case and the file.
cv::Mat readImage(const fs::path& path, const std::string& caseId) {
  try {
    return loadRigImage(path);
  } catch (const RigError& e) {
    throw CameraError(CameraErrorKind::kBadData, "rig case " + caseId + ": " + e.what());
  }
}

/// readImage, keeping the file's bytes (the still as this camera delivers it).
EncodedRigImage readEncodedImage(const fs::path& path, const std::string& caseId) {
  try {
    return loadRigImageWithBytes(path);
  } catch (const RigError& e) {
    throw CameraError(CameraErrorKind::kBadData, "rig case " + caseId + ": " + e.what());
  }
}

/// Reads only the size of an image from its header (PNG IHDR, JPEG SOFn); nullopt when the
/// header is not understood, and the caller decodes the whole file instead.
std::optional<cv::Size> headerSize(const fs::path& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) {
    return std::nullopt;
  }
  // The JPEG frame header follows the APPn/DQT/DHT segments, each at most 64 KiB.
  std::vector<unsigned char> h(1u << 18);
  const std::size_t n = std::fread(h.data(), 1, h.size(), f);
  std::fclose(f);
  auto be16 = [&](std::size_t o) {
    return static_cast<int>((static_cast<unsigned>(h[o]) << 8) | h[o + 1]);
  };
  static const unsigned char kSig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (n >= 24 && std::equal(kSig, kSig + 8, h.begin()) &&
      std::string(h.begin() + 12, h.begin() + 16) == "IHDR") {
    if (be16(16) != 0 || be16(20) != 0)
      return std::nullopt;  // beyond 65535 px: let the decoder judge
    return cv::Size(be16(18), be16(22));
  }
  if (n < 4 || h[0] != 0xFF || h[1] != 0xD8) {
    return std::nullopt;
  }
  std::size_t o = 2;
  while (o + 4 <= n) {
    if (h[o] != 0xFF)
      return std::nullopt;
    const unsigned m = h[o + 1];
    if (m == 0xFF) {  // fill byte
      ++o;
      continue;
    }
    if (m == 0x01 || (m >= 0xD0 && m <= 0xD7)) {  // markers without a length
      o += 2;
      continue;
    }
    const bool sof = m >= 0xC0 && m <= 0xCF && m != 0xC4 && m != 0xC8 && m != 0xCC;
    if (sof) {
      if (o + 9 > n)
        return std::nullopt;
      return cv::Size(be16(o + 7), be16(o + 5));
    }
    if (m == 0xD9 || m == 0xDA)  // end of image or start of scan before any frame header
      return std::nullopt;
    o += 2 + static_cast<std::size_t>(be16(o + 2));
  }
  return std::nullopt;
}

void requireSamePairSize(const cv::Mat& loaded, Shot shot, const fs::path& caseDir,
                         const std::string& caseId) {
  const Shot other = shot == Shot::kDressed ? Shot::kEmpty : Shot::kDressed;
  const fs::path otherPath = framePath(caseDir, other, caseId);
  std::optional<cv::Size> otherSize = headerSize(otherPath);
  if (!otherSize) {
    otherSize = readImage(otherPath, caseId).size();
  }
  const cv::Size emptySize = shot == Shot::kEmpty ? loaded.size() : *otherSize;
  const cv::Size dressedSize = shot == Shot::kDressed ? loaded.size() : *otherSize;
  try {
    requireSameSize(cv::Mat(emptySize, CV_8UC1, cv::Scalar(0)),
                    cv::Mat(dressedSize, CV_8UC1, cv::Scalar(0)),
                    "rig case " + caseId + " (" + caseDir.string() + ")");
  } catch (const std::invalid_argument& e) {
    throw CameraError(CameraErrorKind::kBadData, e.what());
  }
}

class RigSceneSource final : public SceneSource {
 public:
  explicit RigSceneSource(fs::path rigDir) : rigDir_(std::move(rigDir)) {}

  std::string describe() const override { return rigDir_.string(); }

  void open() override {
    std::error_code ec;
    if (!fs::is_directory(rigDir_, ec)) {
      throw CameraError(CameraErrorKind::kNotFound, "no rig folder at " + rigDir_.string());
    }
    // A missing index is a missing device; anything wrong inside the rig is bad data.
    if (!fs::is_regular_file(rigDir_ / "rig.json", ec)) {
      throw CameraError(CameraErrorKind::kNotFound,
                        (rigDir_ / "rig.json").string() + ": missing (not a rig folder)");
    }
    try {
      cases_ = readRig(rigDir_).cases;
    } catch (const RigError& e) {
      throw CameraError(CameraErrorKind::kBadData, e.what());
    }
    if (cases_.empty()) {
      throw CameraError(CameraErrorKind::kBadData,
                        (rigDir_ / "rig.json").string() + ": the rig lists no cases");
    }
  }

  std::size_t caseCount() const override { return cases_.size(); }
  std::string caseId(std::size_t index) const override { return cases_.at(index).id; }

  SceneImage load(std::size_t index, Shot shot) override {
    const RigCaseInfo& ref = cases_.at(index);
    SceneImage out;
    out.caseId = ref.id;
    out.source = framePath(ref.dir, shot, ref.id);
    EncodedRigImage image = readEncodedImage(out.source, ref.id);
    out.bgr = image.bgr;
    if (!image.mediaType.empty()) {
      out.encoded = std::move(image.bytes);
      out.encodedMediaType = std::move(image.mediaType);
    }
    requireSamePairSize(out.bgr, shot, ref.dir, ref.id);
    out.truthPath = ref.dir / "truth.json";
    return out;
  }

 private:
  fs::path rigDir_;
  std::vector<RigCaseInfo> cases_;
};

}  // namespace

std::unique_ptr<SceneSource> makeRigSceneSource(const fs::path& rigDir) {
  return std::make_unique<RigSceneSource>(rigDir);
}

// --- ReplayCamera --------------------------------------------------------------------------

ReplayCamera::ReplayCamera(std::unique_ptr<SceneSource> source, std::string backend, bool loop)
    : source_(std::move(source)), backend_(std::move(backend)), loop_(loop) {}

ReplayCamera::~ReplayCamera() = default;

std::string ReplayCamera::device() const {
  return source_->describe();
}

void ReplayCamera::open() {
  std::lock_guard lock(mutex_);
  if (!present_) {
    throw CameraError(CameraErrorKind::kNotFound,
                      "no " + backend_ + " camera at " + source_->describe() + " (unplugged)");
  }
  if (open_) {
    return;
  }
  source_->open();
  open_ = true;
  disconnected_ = false;
  if (case_ >= source_->caseCount()) {
    case_ = 0;
  }
}

void ReplayCamera::close() noexcept {
  std::lock_guard lock(mutex_);
  open_ = false;
  previewRunning_ = false;
  resumePreview_ = false;
  disconnected_ = false;
}

bool ReplayCamera::isOpen() const {
  std::lock_guard lock(mutex_);
  return open_;
}

void ReplayCamera::requireUsable(const char* what) const {
  if (!open_) {
    throw CameraError(CameraErrorKind::kState, std::string(what) + ": " + backend_ + " camera at " +
                                                   source_->describe() + " is not open");
  }
  if (disconnected_) {
    throw CameraError(CameraErrorKind::kDisconnected,
                      backend_ + " camera at " + source_->describe() + " disconnected");
  }
}

void ReplayCamera::configure(const CameraConfig& config) {
  std::lock_guard lock(mutex_);
  requireUsable("configure");
  if (config.stillWidth < 0 || config.stillHeight < 0 || config.previewWidth < 0 ||
      config.previewHeight < 0 || config.timeout.count() <= 0 || config.settleFrames < 0 ||
      (config.stillWidth == 0) != (config.stillHeight == 0)) {
    throw CameraError(CameraErrorKind::kUnsupported,
                      backend_ +
                          " camera: invalid configuration (negative or half-given size, "
                          "or non-positive timeout)");
  }
  if (config.pixelFormat == PixelFormat::kMjpeg || config.pixelFormat == PixelFormat::kYuyv) {
    throw CameraError(CameraErrorKind::kUnsupported,
                      backend_ + " camera serves BGR images; pixel format " +
                          toString(config.pixelFormat) + " is not offered");
  }
  config_ = config;
}

CameraConfig ReplayCamera::config() const {
  std::lock_guard lock(mutex_);
  return config_;
}

cv::Size ReplayCamera::stillSize() const {
  std::lock_guard lock(mutex_);
  if (config_.stillWidth > 0) {
    return {config_.stillWidth, config_.stillHeight};
  }
  return lastStillSize_;
}

cv::Size ReplayCamera::previewSize() const {
  std::lock_guard lock(mutex_);
  if (!lastShown_) {
    return {config_.previewWidth, config_.previewHeight};
  }
  return scaled(lastShown_->bgr, {config_.previewWidth, config_.previewHeight}).size();
}

void ReplayCamera::lockSettings(const CaptureSettings& settings) {
  std::lock_guard lock(mutex_);
  requireUsable("lockSettings");
  if (settings.exposureUs <= 0 || settings.analogueGain < 1.0 || settings.whiteBalanceKelvin <= 0) {
    throw CameraError(CameraErrorKind::kUnsupported,
                      backend_ +
                          " camera: invalid settings (exposureUs and whiteBalanceKelvin "
                          "must be > 0, analogueGain >= 1)");
  }
  settings_ = settings;
}

CaptureSettings ReplayCamera::settings() const {
  std::lock_guard lock(mutex_);
  return settings_;
}

cv::Mat ReplayCamera::scaled(const cv::Mat& bgr, cv::Size target) const {
  if (target.width <= 0 || target.height <= 0 || bgr.empty()) {
    return bgr;
  }
  // Fit inside the target, keeping the aspect ratio (like a camera's binned preview mode).
  const double s = std::min(static_cast<double>(target.width) / bgr.cols,
                            static_cast<double>(target.height) / bgr.rows);
  const cv::Size size(std::max(1, static_cast<int>(bgr.cols * s + 0.5)),
                      std::max(1, static_cast<int>(bgr.rows * s + 0.5)));
  if (size == bgr.size()) {
    return bgr;
  }
  cv::Mat out;
  cv::resize(bgr, out, size, 0, 0, s < 1.0 ? cv::INTER_AREA : cv::INTER_LINEAR);
  return out;
}

Frame ReplayCamera::makeFrame(const SceneImage& image, bool preview, Shot shot) {
  Frame f;
  f.meta.sequence = sequence_++;
  f.meta.timestamp = std::chrono::duration_cast<std::chrono::nanoseconds>(
      std::chrono::steady_clock::now().time_since_epoch());
  f.meta.preview = preview;
  f.meta.backend = backend_;
  f.meta.device = source_->describe();
  f.meta.pixelFormat = "BGR888";
  f.meta.shot = shot;
  f.meta.caseId = image.caseId;
  f.meta.truthPath = image.truthPath;
  if (!settings_.autoExposure) {
    f.meta.exposureUs = settings_.exposureUs;
    f.meta.analogueGain = settings_.analogueGain;
  }
  if (!settings_.autoWhiteBalance) {
    f.meta.whiteBalanceKelvin = settings_.whiteBalanceKelvin;
    f.meta.redGain = settings_.redGain;
    f.meta.blueGain = settings_.blueGain;
  }
  return f;
}

Frame ReplayCamera::captureStill(const StillRequest& request) {
  std::unique_lock lock(mutex_);
  requireUsable("captureStill");
  if (!request.caseId.empty()) {
    lock.unlock();
    selectCase(request.caseId);
    lock.lock();
  }
  if (exhausted_) {
    throw CameraError(CameraErrorKind::kNotFound,
                      backend_ + " camera at " + source_->describe() + ": all " +
                          std::to_string(source_->caseCount()) + " cases served (looping is off)");
  }
  const Shot shot = request.shot == Shot::kAny ? nextShot_ : request.shot;
  const std::size_t index = case_;
  const auto latency = latency_;
  const auto timeout = config_.timeout;
  lock.unlock();
  std::this_thread::sleep_for(std::min(latency, timeout));
  lock.lock();
  requireUsable("captureStill");  // may have been unplugged while we waited
  if (latency > timeout) {
    throw CameraError(CameraErrorKind::kTimeout, "no frame from " + backend_ + " camera at " +
                                                     source_->describe() + " within " +
                                                     std::to_string(timeout.count()) + " ms");
  }
  if (corruptLeft_ > 0) {
    --corruptLeft_;
    ++dropped_;
    throw CameraError(CameraErrorKind::kBadData, backend_ + " camera at " + source_->describe() +
                                                     ": frame of case " + source_->caseId(index) +
                                                     " arrived corrupt (injected fault)");
  }
  SceneImage image = source_->load(index, shot);
  lastStillSize_ = image.bgr.size();
  if (config_.stillWidth > 0 &&
      image.bgr.size() != cv::Size(config_.stillWidth, config_.stillHeight)) {
    cv::Mat resized;
    cv::resize(image.bgr, resized, {config_.stillWidth, config_.stillHeight}, 0, 0, cv::INTER_AREA);
    image.bgr = resized;
    image.encoded.clear();  // the file's bytes are no longer this frame
    image.encodedMediaType.clear();
  }
  Frame frame = makeFrame(image, false, shot);
  frame.bgr = image.bgr;
  // The file as it is, like a camera's own JPEG: the station stores it without encoding again.
  frame.encoded = std::move(image.encoded);
  frame.encodedMediaType = std::move(image.encodedMediaType);
  lastShown_ = std::move(image);
  // Advance: a dressed frame completes the pair.
  if (shot == Shot::kDressed) {
    nextShot_ = Shot::kEmpty;
    if (case_ + 1 < source_->caseCount()) {
      ++case_;
    } else if (loop_) {
      case_ = 0;
    } else {
      exhausted_ = true;
    }
  } else {
    nextShot_ = Shot::kDressed;
  }
  return frame;
}

void ReplayCamera::startPreview() {
  std::lock_guard lock(mutex_);
  requireUsable("startPreview");
  previewRunning_ = true;
}

std::optional<Frame> ReplayCamera::nextPreviewFrame(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  requireUsable("nextPreviewFrame");
  if (!previewRunning_) {
    throw CameraError(CameraErrorKind::kState, "nextPreviewFrame: preview of " + backend_ +
                                                   " camera at " + source_->describe() +
                                                   " is not running");
  }
  const auto latency = latency_;
  lock.unlock();
  std::this_thread::sleep_for(std::min(latency, timeout));
  lock.lock();
  requireUsable("nextPreviewFrame");
  if (latency > timeout) {
    return std::nullopt;
  }
  if (corruptLeft_ > 0) {
    --corruptLeft_;
    ++dropped_;
    return std::nullopt;
  }
  if (!lastShown_) {
    lastShown_ = source_->load(case_, Shot::kEmpty);
  }
  Frame frame = makeFrame(*lastShown_, true, Shot::kAny);
  frame.bgr = scaled(lastShown_->bgr, {config_.previewWidth, config_.previewHeight}).clone();
  return frame;
}

void ReplayCamera::stopPreview() noexcept {
  std::lock_guard lock(mutex_);
  previewRunning_ = false;
}

bool ReplayCamera::previewRunning() const {
  std::lock_guard lock(mutex_);
  return previewRunning_;
}

bool ReplayCamera::reconnect() {
  bool wantPreview = false;
  {
    std::lock_guard lock(mutex_);
    wantPreview = previewRunning_ || resumePreview_;
    open_ = false;
    previewRunning_ = false;
    disconnected_ = false;
    resumePreview_ = wantPreview;
    if (!present_) {
      return false;
    }
  }
  open();
  std::lock_guard lock(mutex_);
  previewRunning_ = wantPreview;
  resumePreview_ = false;
  return true;
}

void ReplayCamera::setLatency(std::chrono::milliseconds latency) {
  std::lock_guard lock(mutex_);
  latency_ = latency;
}

void ReplayCamera::injectCorruptFrames(int count) {
  std::lock_guard lock(mutex_);
  corruptLeft_ = std::max(0, count);
}

void ReplayCamera::unplug() {
  std::lock_guard lock(mutex_);
  present_ = false;
  if (open_) {
    disconnected_ = true;
  }
}

void ReplayCamera::replug() {
  std::lock_guard lock(mutex_);
  present_ = true;
}

std::size_t ReplayCamera::currentCase() const {
  std::lock_guard lock(mutex_);
  return case_;
}

std::size_t ReplayCamera::caseCount() const {
  std::lock_guard lock(mutex_);
  return open_ ? source_->caseCount() : 0;
}

void ReplayCamera::selectCase(const std::string& caseId) {
  std::lock_guard lock(mutex_);
  requireUsable("selectCase");
  const std::size_t n = source_->caseCount();
  for (std::size_t i = 0; i < n; ++i) {
    if (source_->caseId(i) == caseId) {
      case_ = i;
      nextShot_ = Shot::kEmpty;
      exhausted_ = false;
      lastShown_.reset();
      return;
    }
  }
  std::string known;
  for (std::size_t i = 0; i < std::min<std::size_t>(n, 5); ++i) {
    known += (i ? ", " : "") + source_->caseId(i);
  }
  throw CameraError(CameraErrorKind::kNotFound, backend_ + " camera at " + source_->describe() +
                                                    ": no case '" + caseId + "' (cases: " + known +
                                                    (n > 5 ? ", ..." : "") + ")");
}

std::uint64_t ReplayCamera::framesDropped() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

}  // namespace garmcap::capture
