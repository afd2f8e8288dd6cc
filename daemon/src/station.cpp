#include "garmcap/daemon/station.h"

#include <spdlog/spdlog.h>

#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/post.hpp>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <thread>
#include <utility>

#include "garmcap/capture/camera.h"
#include "garmcap/capture/gpio.h"
#include "garmcap/daemon/disk_full.h"
#include "garmcap/daemon/tape.h"

namespace garmcap::daemon {

namespace asio = boost::asio;
using Clock = std::chrono::steady_clock;

static long long msBetween(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(b - a).count();
}

const char* toString(StationState s) {
  switch (s) {
    case StationState::kUncalibrated:
      return "uncalibrated";
    case StationState::kReady:
      return "ready";
    case StationState::kCapturing:
      return "capturing";
    case StationState::kProcessing:
      return "processing";
    case StationState::kError:
      return "error";
    case StationState::kStopping:
      return "stopping";
  }
  return "?";
}

std::uint8_t ledPattern(StationState s) {
  switch (s) {
    case StationState::kUncalibrated:
      return 0b00001111;  // 1 Hz blink
    case StationState::kReady:
      return 0b11111111;  // steady
    case StationState::kCapturing:
      return 0b01010101;  // 4 Hz flicker
    case StationState::kProcessing:
      return 0b00110011;  // 2 Hz blink
    case StationState::kError:
      return 0b00000101;  // double flash
    case StationState::kStopping:
      return 0;
  }
  return 0;
}

const char* toString(JobKind k) {
  switch (k) {
    case JobKind::kEmpty:
      return "empty";
    case JobKind::kDressed:
      return "dressed";
    case JobKind::kRerun:
      return "rerun";
  }
  return "?";
}

namespace {

std::string encodePng(const cv::Mat& image) {
  std::vector<unsigned char> buf;
  if (!cv::imencode(".png", image, buf, {cv::IMWRITE_PNG_COMPRESSION, 1}))
    throw std::runtime_error("cannot encode a PNG image");
  return std::string(buf.begin(), buf.end());
}

// The photos shops show are JPEG on white (full resolution PNGs run to tens of MB, and shops
// recompress them anyway); the cut-out keeps its alpha in PNG, the review masks stay lossless.
bool storedAsJpeg(const std::string& kind) {
  return kind == "product" || kind == "product_4x5";
}

std::string encodeJpeg(const cv::Mat& image) {
  std::vector<unsigned char> buf;
  if (!cv::imencode(".jpg", image, buf,
                    {cv::IMWRITE_JPEG_QUALITY, 90, cv::IMWRITE_JPEG_OPTIMIZE, 1}))
    throw std::runtime_error("cannot encode a JPEG image");
  return std::string(buf.begin(), buf.end());
}

// The same photos as WebP too, stored beside the JPEG as "<kind>_webp": shops that take WebP
// serve them a quarter to a third smaller. Quality 88 looks as the JPEG at 90 does (SSIM of the
// luma within 0.003 of it, PSNR higher; tests/bench/product_photo_bench's second table).
constexpr int kWebpQuality = 88;
constexpr const char* kWebpKindSuffix = "_webp";

// Whether this OpenCV can write WebP (Debian's links libwebp); asked once, said once if not.
bool webpAvailable() {
  static const bool available = [] {
    const bool yes = cv::haveImageWriter(".webp");
    if (!yes)
      spdlog::warn(
          "station: this OpenCV cannot write WebP; product photos are stored as JPEG only");
    return yes;
  }();
  return available;
}

std::string encodeWebp(const cv::Mat& image) {
  std::vector<unsigned char> buf;
  if (!cv::imencode(".webp", image, buf, {cv::IMWRITE_WEBP_QUALITY, kWebpQuality}))
    throw std::runtime_error("cannot encode a WebP image");
  return std::string(buf.begin(), buf.end());
}

cv::Mat decodeImage(const std::string& bytes, const std::string& what) {
  cv::Mat raw(1, static_cast<int>(bytes.size()), CV_8U, const_cast<char*>(bytes.data()));
  cv::Mat img = cv::imdecode(raw, cv::IMREAD_COLOR);
  if (img.empty())
    throw std::runtime_error("cannot decode the stored " + what);
  return img;
}

// Simulated rig only: a camera that can be "unplugged" to exercise the disconnect paths, and
// whose stills can be made slow (a long exposure, a driver that hangs) so that the camera can
// also disappear during a still.
class UnpluggableCamera : public capture::Camera {
 public:
  UnpluggableCamera(std::unique_ptr<capture::Camera> inner, std::shared_ptr<std::atomic<bool>> off,
                    std::shared_ptr<std::atomic<int>> stillDelayMs)
      : inner_(std::move(inner)), off_(std::move(off)), stillDelayMs_(std::move(stillDelayMs)) {}
  std::string backend() const override { return inner_->backend(); }
  std::string device() const override { return inner_->device(); }
  void open() override {
    check();
    inner_->open();
  }
  void close() noexcept override { inner_->close(); }
  bool isOpen() const override { return inner_->isOpen(); }
  void configure(const capture::CameraConfig& c) override {
    check();
    inner_->configure(c);
  }
  capture::CameraConfig config() const override { return inner_->config(); }
  cv::Size stillSize() const override { return inner_->stillSize(); }
  cv::Size previewSize() const override { return inner_->previewSize(); }
  void lockSettings(const capture::CaptureSettings& s) override { inner_->lockSettings(s); }
  capture::CaptureSettings settings() const override { return inner_->settings(); }
  std::vector<std::string> unsupportedSettings() const override {
    return inner_->unsupportedSettings();
  }
  capture::Frame captureStill(const capture::StillRequest& r) override {
    check();
    // The simulated exposure: an unplug during it fails the still as a real disconnect would.
    const auto until = Clock::now() + std::chrono::milliseconds(stillDelayMs_->load());
    while (Clock::now() < until) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      if (*off_)
        throw capture::CameraError(
            capture::CameraErrorKind::kDisconnected,
            "camera " + inner_->device() + " disconnected during the still (simulated unplug)");
    }
    return inner_->captureStill(r);
  }
  void startPreview() override {
    check();
    inner_->startPreview();
  }
  std::optional<capture::Frame> nextPreviewFrame(std::chrono::milliseconds t) override {
    check();
    return inner_->nextPreviewFrame(t);
  }
  void stopPreview() noexcept override { inner_->stopPreview(); }
  bool previewRunning() const override { return inner_->previewRunning(); }
  bool reconnect() override {
    if (*off_)
      return false;
    return inner_->reconnect();
  }

 private:
  void check() const {
    if (*off_)
      throw capture::CameraError(capture::CameraErrorKind::kDisconnected,
                                 "camera " + inner_->device() + " disconnected (simulated unplug)");
  }
  std::unique_ptr<capture::Camera> inner_;
  std::shared_ptr<std::atomic<bool>> off_;
  std::shared_ptr<std::atomic<int>> stillDelayMs_;
};

// Settings the running objects were built from (camera, GPIO, HTTP server, data folder): a
// reload cannot apply them, so it names them instead of silently ignoring them.
std::vector<std::string> restartOnlyChanges(const Config& a, const Config& b) {
  std::vector<std::string> out;
  auto check = [&](bool differ, const char* key) {
    if (differ)
      out.push_back(key);
  };
  check(a.cameraBackend != b.cameraBackend, "[camera] backend");
  check(a.cameraDevice != b.cameraDevice, "[camera] device");
  check(a.formPath != b.formPath, "[camera] form");
  check(a.stillWidth != b.stillWidth || a.stillHeight != b.stillHeight,
        "[camera] still_width/still_height");
  check(a.gpioBackend != b.gpioBackend || a.buttonChip != b.buttonChip ||
            a.buttonLine != b.buttonLine || a.ledChip != b.ledChip || a.ledLine != b.ledLine,
        "[gpio]");
  check(a.dataDir != b.dataDir, "[paths] data");
  check(a.listenAddress != b.listenAddress || a.listenPort != b.listenPort, "[http] listen");
  check(a.token != b.token, "[http] token");
  check(a.workerThreads != b.workerThreads, "[pipeline] worker_threads");
  return out;
}

}  // namespace

Station::Station(asio::io_context& io, Config config, std::unique_ptr<capture::Camera> camera,
                 std::unique_ptr<capture::Gpio> gpio, std::unique_ptr<CaptureProcessor> processor)
    : io_(io),
      strand_(asio::make_strand(io)),
      config_(std::move(config)),
      gpio_(std::move(gpio)),
      processor_(std::move(processor)),
      unplugged_(std::make_shared<std::atomic<bool>>(false)),
      stillDelayMs_(std::make_shared<std::atomic<int>>(0)),
      ledTimer_(strand_),
      buttonTimer_(strand_),
      previewTimer_(strand_),
      keepAliveTimer_(strand_),
      graceTimer_(strand_),
      cameraRetryTimer_(strand_) {
  shop_ = config_.shop;
  if (camera && simulated())
    camera_ = std::make_unique<UnpluggableCamera>(std::move(camera), unplugged_, stillDelayMs_);
  else
    camera_ = std::move(camera);
  pool_ = std::make_unique<asio::thread_pool>(static_cast<std::size_t>(config_.workerThreads));
  // Downloads (blob reads, exports, pattern files) run apart from the pipeline, so a capture's
  // latency does not depend on how many catalog.zip are being built; two threads, so one long
  // export does not hold up every image.
  servePool_ = std::make_unique<asio::thread_pool>(2);
}

Station::~Station() {
  alive_.reset();  // handlers still queued for the strand now do nothing
  if (buttonDescriptor_) {
    auto* sd = static_cast<asio::posix::stream_descriptor*>(buttonDescriptor_.get());
    sd->release();  // the Button owns the fd
  }
  cameraThread_.join();
  servePool_->join();
  pool_->join();
  if (camera_)
    camera_->close();
}

bool Station::simulated() const {
  return config_.cameraBackend == "synthetic" || config_.cameraBackend == "replay";
}

bool Station::setCameraUnplugged(bool unplugged) {
  if (!simulated())
    return false;
  *unplugged_ = unplugged;
  return true;
}

bool Station::setSimulatedStillDelay(std::chrono::milliseconds delay) {
  if (!simulated())
    return false;
  *stillDelayMs_ = static_cast<int>(delay.count());
  return true;
}

#ifdef GARMCAP_TEST_HOOKS
void Station::stallLoopForTest(std::chrono::milliseconds duration, std::function<void()> done) {
  postToStrand([duration, done = std::move(done)] {
    spdlog::warn("station: test hook: blocking the event loop for {} ms", duration.count());
    std::this_thread::sleep_for(duration);  // deliberately on the loop's only thread
    done();
  });
}
#endif

void Station::start() {
  std::filesystem::create_directories(config_.dataDir);
  const auto catalogFile = std::filesystem::path(config_.dataDir) / "catalog.sqlite";
  try {
    catalog_ = std::make_unique<Catalog>(catalogFile);
  } catch (const DiskFull& e) {
    // A full disk must not keep the station down: what is stored can still be browsed and
    // exported. Nothing is written until garmcapd is restarted with space freed.
    catalog_ = std::make_unique<Catalog>(catalogFile, Catalog::Mode::kReadOnly);
    readOnly_ =
        "the station's disk is full: started read-only, nothing can be captured or "
        "changed; free space in " +
        config_.dataDir + " and restart garmcapd";
    spdlog::error("station: {} ({})", readOnly_, e.what());
  }
  store_ = std::make_unique<ContentStore>(std::filesystem::path(config_.dataDir) / "blobs");
  loadShopSettings();
  if (!readOnly_.empty()) {
    lastError_ = readOnly_;
    if (auto cal = catalog_->latestCalibration(); cal && store_->contains(cal->emptySha256))
      calibrated_ = true, calibrationId_ = cal->id;
    state_ = StationState::kError;
    lastLoopTick_ = Clock::now();
    postToStrand([this] {
      startGpio();
      ledTick();
      keepAliveTick();
    });
    return;
  }
  // A job that was running when the process died is not retried: it may be what killed it,
  // and a restart loop would follow. Its stored frames stay, so the item can be re-captured.
  const auto interrupted =
      catalog_->failInterruptedJobs("interrupted: garmcapd stopped before the job finished");
  for (auto id : interrupted)
    spdlog::warn("station: job {} was interrupted; marked failed", id);
  // Queued jobs never started: an accepted press is run after a restart, unless it is so old
  // that the garment has likely left the form.
  const auto maxAge = std::chrono::seconds(config_.resumeQueuedS);
  for (auto id : catalog_->expireQueuedJobs(maxAge, "expired: garmcapd was down for more than " +
                                                        std::to_string(config_.resumeQueuedS) +
                                                        " s before the job could start"))
    spdlog::warn("station: queued job {} expired while garmcapd was down", id);
  for (const Job& j : catalog_->queuedJobs()) {
    Pending p{JobKind::kDressed, j.id, j.sku, j.itemId.value_or(0), false, 1};
    if (j.kind == toString(JobKind::kEmpty))
      p.kind = JobKind::kEmpty;
    else if (j.kind == toString(JobKind::kRerun))
      p.kind = JobKind::kRerun;
    queue_.push_back(std::move(p));
    spdlog::info("station: job {} ({}) resumed from the queue", j.id, j.kind);
  }
  if (!catalog_->readOnly())
    reclaimStorage(std::nullopt);
  const std::size_t swept = store_->sweepOrphans(catalog_->referencedImages());
  if (swept)
    spdlog::warn("station: removed {} orphaned blobs left by a crash", swept);
  if (auto cal = catalog_->latestCalibration(); cal && store_->contains(cal->emptySha256)) {
    calibrated_ = true;
    calibrationId_ = cal->id;
  }
  state_ = calibrated_ ? StationState::kReady : StationState::kUncalibrated;
  lastLoopTick_ = Clock::now();
  postToStrand([this] {
    openCamera();
    startGpio();
    ledTick();
    keepAliveTick();
    startNext();  // resumed jobs; the camera thread opens the camera before their stills
  });
}

void Station::openCamera() {
  if (!camera_) {
    if (cameraError_.empty())
      cameraError_ = "no camera configured";
    if (!running_ && !stopping_)
      setState(StationState::kError);
    return;
  }
  capture::CameraConfig cc;
  cc.stillWidth = config_.stillWidth;
  cc.stillHeight = config_.stillHeight;
  cc.timeout = std::chrono::milliseconds(config_.captureTimeoutMs);
  asio::post(cameraThread_, [this, cc] {
    std::string error;
    try {
      if (!camera_->isOpen())
        camera_->open();
      camera_->configure(cc);
    } catch (const std::exception& e) {
      error = e.what();
    }
    postToStrand([this, error] {
      cameraOpen_ = error.empty();
      cameraError_ = error;
      if (!error.empty()) {
        spdlog::error("station: camera {} unavailable: {}", camera_->device(), error);
        if (!running_ && !stopping_)
          setState(StationState::kError);
        scheduleCameraRetry();
        return;
      }
      spdlog::info("station: camera {} ({}) open", camera_->device(), camera_->backend());
      cameraRetryDelay_ = std::chrono::milliseconds(0);
      if (state_ == StationState::kError && !running_ && !stopping_ && readOnly_.empty()) {
        lastError_.clear();
        setState(calibrated_ ? StationState::kReady : StationState::kUncalibrated);
        startNext();
      }
    });
  });
}

void Station::scheduleCameraRetry() {
  if (!camera_ || stopping_ || cameraRetryPending_)
    return;
  using std::chrono::milliseconds;
  cameraRetryDelay_ = cameraRetryDelay_.count() == 0
                          ? milliseconds(500)
                          : std::min(cameraRetryDelay_ * 2, milliseconds(5000));
  cameraRetryPending_ = true;
  spdlog::info("station: trying the camera again in {} ms", cameraRetryDelay_.count());
  cameraRetryTimer_.expires_after(cameraRetryDelay_);
  cameraRetryTimer_.async_wait([this](boost::system::error_code ec) {
    cameraRetryPending_ = false;
    if (!ec && !stopping_ && state_ == StationState::kError)
      openCamera();
  });
}

// --- GPIO ------------------------------------------------------------------------------------

void Station::startGpio() {
  if (!gpio_)
    return;
  auto sd = std::make_shared<asio::posix::stream_descriptor>(strand_, gpio_->button().eventFd());
  buttonDescriptor_ = sd;
  waitButton();
}

void Station::waitButton() {
  auto* sd = static_cast<asio::posix::stream_descriptor*>(buttonDescriptor_.get());
  sd->async_wait(asio::posix::stream_descriptor::wait_read, [this](boost::system::error_code ec) {
    if (ec)
      return;  // cancelled at shutdown
    try {
      for (const auto& e : gpio_->button().readEvents()) {
        if (e.kind == capture::ButtonEvent::Kind::kShortPress)
          press();
        if (e.kind == capture::ButtonEvent::Kind::kLongPress)
          longPress();
      }
    } catch (const std::exception& e) {
      spdlog::error("station: reading the button failed: {}", e.what());
    }
    armButtonTimer();
    waitButton();
  });
}

void Station::armButtonTimer() {
  auto deadline = gpio_->button().nextDeadline();
  if (!deadline)
    return;
  buttonTimer_.expires_at(*deadline);
  buttonTimer_.async_wait([this](boost::system::error_code ec) {
    if (ec)
      return;
    try {
      for (const auto& e : gpio_->button().tick(Clock::now())) {
        if (e.kind == capture::ButtonEvent::Kind::kShortPress)
          press();
        if (e.kind == capture::ButtonEvent::Kind::kLongPress)
          longPress();
      }
    } catch (const std::exception& e) {
      spdlog::error("station: button tick failed: {}", e.what());
    }
    armButtonTimer();
  });
}

void Station::ledTick() {
  lastLoopTick_ = Clock::now();
  if (gpio_ && gpio_->statusLed()) {
    const bool on = (ledPattern(state_) >> (ledTick_ % 8)) & 1;
    try {
      gpio_->statusLed()->set(on);
    } catch (const std::exception& e) {
      spdlog::warn("station: LED: {}", e.what());
    }
  }
  ++ledTick_;
  ledTimer_.expires_after(std::chrono::milliseconds(125));
  ledTimer_.async_wait([this](boost::system::error_code ec) {
    if (!ec)
      ledTick();
  });
}

void Station::keepAliveTick() {
  // SSE comments keep idle proxies and browsers from dropping the event stream.
  broadcast("", nullptr);
  keepAliveTimer_.expires_after(std::chrono::seconds(15));
  keepAliveTimer_.async_wait([this](boost::system::error_code ec) {
    if (!ec)
      keepAliveTick();
  });
}

// --- submissions -----------------------------------------------------------------------------

void Station::submit(JobKind kind, std::string sku, std::int64_t itemId,
                     std::function<void(SubmitResult)> done) {
  postToStrand([this, kind, sku = std::move(sku), itemId, done = std::move(done)]() mutable {
    submitOnStrand(kind, std::move(sku), itemId, false, std::move(done));
  });
}

void Station::press(std::function<void(SubmitResult)> done) {
  postToStrand([this, done = std::move(done)]() mutable {
    // Debounce presses into the press already waiting in the queue: staff pressing again
    // while a job runs mean "yes, capture", not "capture twice".
    for (auto& p : queue_) {
      if (p.fromButton) {
        ++p.presses;
        spdlog::info("station: press merged into queued job {} ({} presses)", p.jobId, p.presses);
        if (done)
          done({p.jobId, 202, "", true});
        return;
      }
    }
    // What the press means is decided when it is taken, from the calibration state then.
    const bool calibratedSoon =
        calibrated_ ||
        std::any_of(queue_.begin(), queue_.end(),
                    [](const Pending& p) { return p.kind == JobKind::kEmpty; }) ||
        (running_ && running_->request.kind == JobKind::kEmpty);
    submitOnStrand(calibratedSoon ? JobKind::kDressed : JobKind::kEmpty, "", 0, true,
                   std::move(done));
  });
}

void Station::longPress() {
  postToStrand([this] { submitOnStrand(JobKind::kEmpty, "", 0, true, {}); });
}

void Station::submitOnStrand(JobKind kind, std::string sku, std::int64_t itemId, bool fromButton,
                             std::function<void(SubmitResult)> done) {
  auto answer = [&](SubmitResult r) {
    if (done)
      done(std::move(r));
  };
  if (stopping_)
    return answer({std::nullopt, 503, "the station is shutting down", false});
  if (!readOnly_.empty())
    return answer({std::nullopt, 507, readOnly_, false});
  if (static_cast<int>(queue_.size()) >= config_.queueLimit)
    return answer({std::nullopt, 503,
                   "capture queue full (" + std::to_string(config_.queueLimit) + " waiting)",
                   false});
  const bool calibrationComing =
      calibrated_ ||
      std::any_of(queue_.begin(), queue_.end(),
                  [](const Pending& p) { return p.kind == JobKind::kEmpty; }) ||
      (running_ && running_->request.kind == JobKind::kEmpty);
  if (kind == JobKind::kDressed && !calibrationComing && !fromButton)
    return answer({std::nullopt, 409,
                   "the station is not calibrated: capture the bare form first "
                   "(POST /api/capture/empty)",
                   false});
  if (kind == JobKind::kRerun) {
    auto item = catalog_->item(itemId);
    if (!item)
      return answer({std::nullopt, 404, "no item " + std::to_string(itemId), false});
    auto job = item->jobId ? catalog_->job(*item->jobId) : std::nullopt;
    if (!job || job->dressedSha256.empty() || !store_->contains(job->dressedSha256))
      return answer({std::nullopt, 409,
                     "item " + std::to_string(itemId) + " has no stored dressed frame to re-run",
                     false});
    if (!calibrated_)
      return answer({std::nullopt, 409, "the station is not calibrated", false});
  }
  std::int64_t jobId = 0;
  try {
    jobId = catalog_->addJob(toString(kind), sku,
                             kind == JobKind::kRerun ? std::optional(itemId) : std::nullopt);
  } catch (const DiskFull& e) {
    spdlog::error("station: cannot record a job: {}", e.what());
    return answer({std::nullopt, 507, e.what(), false});
  } catch (const std::exception& e) {
    spdlog::error("station: cannot record a job: {}", e.what());
    return answer(
        {std::nullopt, 500, "cannot record the job; the station's log has the details", false});
  }
  queue_.push_back({kind, jobId, std::move(sku), itemId, fromButton, 1});
  spdlog::info("station: job {} ({}) queued{}", jobId, toString(kind),
               fromButton ? " by the button" : "");
  if (auto j = catalog_->job(jobId))
    broadcast("job", jobJson(*j));
  answer({jobId, 202, "", false});
  startNext();
}

// --- the job pipeline --------------------------------------------------------------------------

void Station::setState(StationState s) {
  if (state_ == s)
    return;
  state_ = s;
  broadcast("state", {{"state", toString(s)}, {"last_error", lastError_}});
}

void Station::setStage(const std::string& stage, double progress, bool persist) {
  if (!running_)
    return;
  const bool changed = running_->stage != stage;
  running_->stage = stage;
  running_->progress = progress;
  if (changed)
    running_->stageSince = Clock::now();
  // Persist stage changes only: progress ticks go to subscribers, not to an fsync each.
  if (persist && changed) {
    try {
      catalog_->updateJob(running_->request.jobId, "running", stage, progress);
    } catch (const std::exception& e) {
      spdlog::error("station: cannot update job {}: {}", running_->request.jobId, e.what());
    }
  }
  broadcast("job", {{"id", running_->request.jobId},
                    {"kind", toString(running_->request.kind)},
                    {"state", "running"},
                    {"stage", stage},
                    {"progress", progress},
                    {"item_id", nullptr},
                    {"error", ""}});
}

void Station::startNext() {
  if (running_)
    return;
  // A reload during a job could not swap the processor under the worker using it.
  if (pendingProcessor_ && processorFactory_) {
    processor_ = processorFactory_(*pendingProcessor_);
    pendingProcessor_.reset();
    spdlog::info("station: pipeline options of the reloaded configuration now in use");
  }
  if (queue_.empty() || stopping_)
    return;
  Pending req = queue_.front();
  queue_.pop_front();
  running_ = Running{req, "", 0, Clock::now()};
  if (req.kind == JobKind::kRerun) {
    setState(StationState::kProcessing);
    setStage("loading", 0.05, true);
    auto item = catalog_->item(req.itemId);
    auto job = item && item->jobId ? catalog_->job(*item->jobId) : std::nullopt;
    if (!job)
      return failJob(req, "the item's capture job is gone", false);
    const std::string sha = job->dressedSha256;
    if (!req.sku.size())
      req.sku = item->sku;
    running_->request = req;
    asio::post(*pool_, [this, req, sha] {
      try {
        auto bytes = store_->read(sha);
        if (!bytes)
          throw std::runtime_error("the stored dressed frame " + sha + " is missing");
        cv::Mat frame = decodeImage(*bytes, "dressed frame");
        std::promise<StoredFrame> stored;  // a re-run's frame is stored and recorded already
        stored.set_value({sha, 0, false});
        postToStrand(
            [this, req, frame, f = stored.get_future().share()] { runDressed(req, frame, f); });
      } catch (const std::exception& e) {
        postToStrand([this, req, msg = std::string(e.what())] { failJob(req, msg, false); });
      }
    });
    return;
  }
  setState(StationState::kCapturing);
  setStage("capturing", 0.05, true);
  if (!camera_)
    return failJob(req, "camera: " + cameraError_, true);
  const capture::Shot shot =
      req.kind == JobKind::kEmpty ? capture::Shot::kEmpty : capture::Shot::kDressed;
  capture::CameraConfig cc;
  cc.stillWidth = config_.stillWidth;
  cc.stillHeight = config_.stillHeight;
  cc.timeout = std::chrono::milliseconds(config_.captureTimeoutMs);
  stillInFlight_ = true;
  asio::post(cameraThread_, [this, req, shot, cc] {
    try {
      // After a disconnect the camera is closed: opening it again is the reconnect (and throws
      // kNotFound with the device's name while it is still away).
      if (!camera_->isOpen()) {
        camera_->open();
        camera_->configure(cc);
      }
      capture::StillRequest sr;
      sr.shot = shot;
      const auto t0 = Clock::now();
      capture::Frame frame = camera_->captureStill(sr);
      const auto t1 = Clock::now();
      if (shot == capture::Shot::kDressed) {
        // The pipeline starts on the frame in memory while this thread encodes and stores it
        // (PNG is single-threaded: a second or more at 12 MP); the item waits for the stored
        // frame before it is filed, so the blob is still durable before any row names it.
        auto stored = std::make_shared<std::promise<StoredFrame>>();
        std::shared_future<StoredFrame> frameStored = stored->get_future().share();
        postToStrand([this, req, bgr = frame.bgr, frameStored] {
          cameraOpen_ = true;
          cameraError_.clear();
          runDressed(req, bgr, frameStored);
        });
        try {
          const std::string png = encodePng(frame.bgr);
          const auto t2 = Clock::now();
          stored->set_value({store_->put(png), static_cast<std::int64_t>(png.size()), true});
          spdlog::info("station: job {}: still {} ms, PNG {} ms, stored {} ms", req.jobId,
                       msBetween(t0, t1), msBetween(t1, t2), msBetween(t2, Clock::now()));
        } catch (...) {
          stored->set_exception(std::current_exception());
        }
        postToStrand([this] { stillInFlight_ = false; });
        return;
      }
      const std::string png = encodePng(frame.bgr);
      const auto t2 = Clock::now();
      const std::string sha = store_->put(png);
      spdlog::info("station: job {}: still {} ms, PNG {} ms, stored {} ms", req.jobId,
                   msBetween(t0, t1), msBetween(t1, t2), msBetween(t2, Clock::now()));
      postToStrand([this, req, bgr = frame.bgr, sha, n = static_cast<std::int64_t>(png.size())] {
        stillInFlight_ = false;
        cameraOpen_ = true;
        cameraError_.clear();
        onFrameStored(req, bgr, sha, n);
      });
    } catch (const capture::CameraError& e) {
      const bool gone = e.kind() == capture::CameraErrorKind::kDisconnected ||
                        e.kind() == capture::CameraErrorKind::kNotFound;
      if (gone)
        camera_->close();
      postToStrand([this, req, gone, msg = std::string("camera: ") + e.what()] {
        stillInFlight_ = false;
        if (gone)
          cameraOpen_ = false;
        cameraError_ = msg;
        failJob(req, msg, true);
      });
    } catch (const std::exception& e) {
      postToStrand([this, req, msg = std::string("capture failed: ") + e.what()] {
        stillInFlight_ = false;
        failJob(req, msg, false);
      });
    }
  });
}

void Station::onFrameStored(Pending req, cv::Mat frame, std::string sha, std::int64_t bytes) {
  try {
    catalog_->addImage(sha, "image/png", bytes);
  } catch (const std::exception& e) {
    return failJob(req, std::string("cannot record the frame: ") + e.what(), false);
  }
  runEmpty(std::move(req), std::move(frame), std::move(sha));
}

void Station::runEmpty(Pending req, cv::Mat frame, std::string sha) {
  catalog_->setJobFrames(req.jobId, sha, "");
  setState(StationState::kProcessing);
  setStage("calibration", 0.3, true);
  asio::post(*pool_, [this, req, frame, sha] {
    try {
      auto progress = [this](const std::string& stage, double p) {
        postToStrand([this, stage, p] { setStage(stage, 0.3 + 0.6 * p, false); });
      };
      nlohmann::json calibration = processor_->calibrate(frame, progress);
      // The bare frame the next captures compare with is this one: kept as it is, the first
      // capture does not read and decode its stored PNG again (0.45 s at 12 MP). The PNG is
      // lossless, so it is the frame that decoding would give; keyed by its blob, like a decode.
      if (frame.type() == CV_8UC3) {
        std::lock_guard lock(bareFrameMutex_);
        bareFrameSha_ = sha;
        bareFrame_ = frame;
      }
      postToStrand([this, req, sha, calibration] { onCalibrated(req, sha, calibration); });
    } catch (const std::exception& e) {
      postToStrand([this, req, msg = std::string(e.what())] { failJob(req, msg, false); });
    }
  });
}

void Station::onCalibrated(Pending req, std::string emptySha, nlohmann::json calibration) {
  try {
    const std::int64_t id = catalog_->addCalibration(emptySha, calibration);
    catalog_->finishJob(req.jobId, std::nullopt, id);
    calibrated_ = true;
    calibrationId_ = id;
    lastError_.clear();
    spdlog::info("station: calibration {} made by job {}", id, req.jobId);
  } catch (const std::exception& e) {
    return failJob(req, std::string("cannot store the calibration: ") + e.what(), false);
  }
  finishJob();
}

// The calibration's bare-form frame, decoded once per calibration (a 12 MP PNG takes a few
// hundred milliseconds to read and decode, on every capture before). Called on the worker pool.
cv::Mat Station::bareFrame(const Calibration& cal) {
  {
    std::lock_guard lock(bareFrameMutex_);
    if (bareFrameSha_ == cal.emptySha256 && !bareFrame_.empty())
      return bareFrame_;
  }
  auto bytes = store_->read(cal.emptySha256);
  if (!bytes)
    throw std::runtime_error("the bare-form frame of calibration " + std::to_string(cal.id) +
                             " is missing");
  cv::Mat empty = decodeImage(*bytes, "bare-form frame");
  std::lock_guard lock(bareFrameMutex_);
  bareFrameSha_ = cal.emptySha256;
  bareFrame_ = empty;  // shared, never written: the pipeline reads its frames
  return empty;
}

void Station::runDressed(Pending req, cv::Mat dressed, std::shared_future<StoredFrame> stored) {
  auto cal = catalog_->latestCalibration();
  if (!cal)
    return failJob(req, "the station is not calibrated: capture the bare form first", false);
  setState(StationState::kProcessing);
  setStage("garmcap", 0.2, true);
  const double threshold = config_.reviewBelowConfidence;
  // The shop's tape corrections (daemon/tape.h), fitted here on the strand that owns the catalog
  // from the rows as they are now: a capture (or re-run) started after staff taped garments is
  // corrected, pattern and size run included; items filed before are not rewritten.
  std::shared_ptr<const pipeline::CorrectionTable> corrections;
  try {
    auto table = tapeCorrections(*catalog_);
    if (!table.corrections.empty())
      corrections = std::make_shared<const pipeline::CorrectionTable>(std::move(table));
  } catch (const std::exception& e) {
    return failJob(req, std::string("cannot read the tape corrections: ") + e.what(), false);
  }
  asio::post(*pool_, [this, req, dressed, stored, cal = *cal, threshold, corrections] {
    try {
      const auto t0 = Clock::now();
      // The hang tag is read beside the pipeline (zbar is single-threaded: about a second on a
      // 12 MP frame).
      std::future<std::string> tag;
      if (req.sku.empty())
        tag = std::async(std::launch::async, [dressed] { return decodeHangTagSku(dressed); });
      cv::Mat empty = bareFrame(cal);
      const auto t1 = Clock::now();
      auto progress = [this](const std::string& stage, double p) {
        postToStrand([this, stage, p] { setStage(stage, 0.2 + 0.7 * p, false); });
      };
      ProcessedCapture r = processor_->process(empty, dressed, cal.json, progress, corrections);
      const auto t2 = Clock::now();
      const std::string sku = tag.valid() ? tag.get() : req.sku;
      // Encoding and fsyncing the product images takes a noticeable moment at full resolution.
      postToStrand([this] { setStage("store", 0.92, false); });
      auto item = std::make_shared<NewItem>();
      item->sku = sku;
      item->type = r.type;
      // No title: until staff give one, the API and the exports name the piece from its colour,
      // cut and type ("Navy A-line skirt"), re-derived when staff correct them.
      item->attributes = r.attributes;
      item->confidence = r.confidence;
      item->warnings = r.warnings;
      item->measurementsCm = r.measurementsCm;
      item->patterns = r.patterns;
      item->baseSize = r.baseSize;
      item->sizeGuide = r.sizeGuide;
      item->result = r.result;
      item->calibrationId = cal.id;
      item->jobId = req.jobId;
      item->needsReview = r.confidence < threshold || !r.warnings.empty();
      // Blobs are durable before the transaction that names them (content_store.h).
      for (const auto& [kind, image] : r.images) {
        const bool jpeg = storedAsJpeg(kind);
        const std::string bytes = jpeg ? encodeJpeg(image) : encodePng(image);
        item->images.push_back({kind, store_->put(bytes), jpeg ? "image/jpeg" : "image/png",
                                static_cast<std::int64_t>(bytes.size())});
        if (jpeg && webpAvailable()) {
          const std::string webp = encodeWebp(image);
          item->images.push_back({kind + kWebpKindSuffix, store_->put(webp), "image/webp",
                                  static_cast<std::int64_t>(webp.size())});
        }
      }
      const StoredFrame frame = stored.get();  // throws what storing the still threw
      item->images.push_back({"dressed", frame.sha256, "image/png", 0});
      item->images.push_back({"empty", cal.emptySha256, "image/png", 0});
      spdlog::info(
          "station: job {}: bare frame {} ms, pipeline {} ms, then hang tag, still and "
          "photos stored {} ms",
          req.jobId, msBetween(t0, t1), msBetween(t1, t2), msBetween(t2, Clock::now()));
      postToStrand([this, req, item, frame, emptySha = cal.emptySha256] {
        if (recordFrame(req, emptySha, frame))
          onProcessed(req, item);
      });
    } catch (const std::exception& e) {
      // A failed job keeps its frames, as before (what staff or a developer look at).
      std::optional<StoredFrame> frame;
      try {
        frame = stored.get();
      } catch (const std::exception& se) {
        spdlog::error("station: job {}: the still was not stored either: {}", req.jobId, se.what());
      }
      postToStrand([this, req, frame, emptySha = cal.emptySha256, msg = std::string(e.what())] {
        if (!frame || recordFrame(req, emptySha, *frame))
          failJob(req, msg, false);
      });
    }
  });
}

bool Station::recordFrame(const Pending& req, const std::string& emptySha,
                          const StoredFrame& frame) {
  try {
    if (frame.toRecord)
      catalog_->addImage(frame.sha256, "image/png", frame.bytes);
    catalog_->setJobFrames(req.jobId, emptySha, frame.sha256);
    return true;
  } catch (const std::exception& e) {
    failJob(req, std::string("cannot record the frame: ") + e.what(), false);
    return false;
  }
}

void Station::onProcessed(Pending req, std::shared_ptr<NewItem> item) {
  try {
    setStage("filing", 0.95, false);
    std::int64_t id = 0;
    if (req.kind == JobKind::kRerun) {
      // Keep the original frames on the item; the re-run belongs to the new job.
      for (auto& sha : catalog_->replaceItemResults(req.itemId, *item))
        reclaimCandidates_.push_back(std::move(sha));
      id = req.itemId;
    } else {
      id = catalog_->addItem(*item);
    }
    lastError_.clear();
    spdlog::info("station: job {} filed item {} ({}, confidence {:.2f}{})", req.jobId, id,
                 item->type, item->confidence, item->needsReview ? ", needs review" : "");
  } catch (const std::exception& e) {
    return failJob(req, std::string("cannot file the item: ") + e.what(), false);
  }
  finishJob();
}

void Station::failJob(const Pending& req, const std::string& error, bool cameraFault) {
  spdlog::error("station: job {} ({}) failed: {}", req.jobId, toString(req.kind), error);
  try {
    catalog_->failJob(req.jobId, error);
    unrecordedFailures_.erase(req.jobId);
  } catch (const std::exception& e) {
    // The catalog still says queued or running: keep the outcome in memory so that the job is
    // reported failed with its reason (a full disk, typically) instead of running forever.
    spdlog::error("station: cannot record the failure of job {}: {}", req.jobId, e.what());
    unrecordedFailures_[req.jobId] =
        error + " (this failure could not be stored: " + e.what() + ")";
  }
  lastError_ = error;
  if (cameraFault) {
    running_.reset();
    if (auto j = catalog_->job(req.jobId))
      broadcast("job", jobJson(*j));
    setState(StationState::kError);
    scheduleCameraRetry();
    maybeFinishShutdown();
    startNext();
    return;
  }
  finishJob();
}

void Station::finishJob() {
  if (running_) {
    if (auto j = catalog_->job(running_->request.jobId))
      broadcast("job", jobJson(*j));
  }
  running_.reset();
  setState(calibrated_ ? StationState::kReady : StationState::kUncalibrated);
  if (queue_.empty() && !catalog_->readOnly())
    reclaimStorage(std::exchange(reclaimCandidates_, {}));
  maybeFinishShutdown();
  startNext();
}

void Station::reclaimStorage(std::optional<std::vector<std::string>> candidates) {
  using std::chrono::hours;
  try {
    const auto steadyNow = Clock::now();
    if (!lastRetentionPurge_ || steadyNow - *lastRetentionPurge_ >= hours(1)) {
      lastRetentionPurge_ = steadyNow;
      const auto now = std::chrono::system_clock::now();
      std::vector<std::string> released;
      if (config_.keepDeletedDays > 0)
        released = catalog_->purgeDeletedItems(now - hours(24) * config_.keepDeletedDays,
                                               !config_.hubUrl.empty());
      if (config_.keepFailedFramesDays > 0)
        for (auto& sha :
             catalog_->forgetFailedJobFrames(now - hours(24) * config_.keepFailedFramesDays))
          released.push_back(std::move(sha));
      if (candidates)
        candidates->insert(candidates->end(), released.begin(), released.end());
    }
    if (candidates && candidates->empty())
      return;
    std::uintmax_t bytes = 0;
    std::size_t files = 0;
    for (const std::string& sha : catalog_->dropUnreferencedImages(std::move(candidates))) {
      std::error_code sizeError;
      const auto path = store_->path(sha);
      const std::uintmax_t size = path ? std::filesystem::file_size(*path, sizeError) : 0;
      if (const std::error_code ec = store_->remove(sha)) {
        // Its row is gone: the start-up sweep removes the file.
        spdlog::warn("station: cannot remove reclaimed blob {}: {}", sha, ec.message());
        continue;
      }
      if (path) {
        ++files;
        bytes += sizeError ? 0 : size;
      }
    }
    if (files)
      spdlog::info("station: reclaimed {} image files ({:.1f} MB) that nothing refers to any more",
                   files, static_cast<double>(bytes) / 1e6);
  } catch (const std::exception& e) {
    // Nothing is lost: the rows stay until a later attempt succeeds.
    spdlog::error("station: reclaiming storage failed, tried again after the next job: {}",
                  e.what());
  }
}

// --- status, events ------------------------------------------------------------------------------

nlohmann::json Station::jobJson(const Job& job) const {
  nlohmann::json j = job.toJson();
  if (running_ && running_->request.jobId == job.id && job.state == "running") {
    j["stage"] = running_->stage;
    j["progress"] = running_->progress;
  }
  return j;
}

// The outbox and the rows the hub refused for good (docs/hub.md), so that staff see them; on the
// strand, which owns the catalog.
nlohmann::json Station::hubStatusJson() {
  nlohmann::json h = hubStatus_ ? hubStatus_() : nlohmann::json::object();
  h["outbox"] = catalog_->outboxSize();
  h["refused_count"] = catalog_->refusedOutboxSize();
  nlohmann::json refused = nlohmann::json::array();
  for (const auto& r : catalog_->refusedOutbox(20))
    refused.push_back({{"seq", r.row.seq},
                       {"kind", r.row.kind},
                       {"item_id", r.row.itemId},
                       {"http_status", r.httpStatus},
                       {"reason", r.reason},
                       {"refused_at", r.refusedAt}});
  h["refused"] = std::move(refused);
  return h;
}

nlohmann::json Station::statusJson() {
  nlohmann::json s{{"state", toString(state_)},       {"calibrated", calibrated_},
                   {"read_only", !readOnly_.empty()}, {"queue", queue_.size()},
                   {"last_error", lastError_},        {"simulated", simulated()},
                   {"led", ledPattern(state_)},       {"healthy", healthy()}};
  s["calibration_id"] = calibrationId_ ? nlohmann::json(*calibrationId_) : nlohmann::json(nullptr);
  if (running_) {
    if (auto j = catalog_->job(running_->request.jobId))
      s["job"] = jobJson(*j);
  } else {
    s["job"] = nullptr;
  }
  s["camera"] = {{"backend", camera_ ? camera_->backend() : ""},
                 {"device", camera_ ? camera_->device() : ""},
                 {"open", cameraOpen_},
                 {"error", cameraError_}};
  s["gpio"] = gpio_ ? gpio_->backend() : "none";
  // The reloadable settings in force, so that an operator (and the tests) can see what a SIGHUP
  // did or refused to do.
  s["config"] = {{"review_below_confidence", config_.reviewBelowConfidence},
                 {"queue_limit", config_.queueLimit},
                 {"resume_queued_s", config_.resumeQueuedS},
                 {"keep_deleted_days", config_.keepDeletedDays},
                 {"keep_failed_frames_days", config_.keepFailedFramesDays},
                 {"naming_template", config_.namingTemplate},
                 {"size_chart", config_.sizeChart},
                 {"product_images", config_.makeProductImages},
                 {"texture", config_.makeTexture},
                 {"product_size_px", config_.productSizePx},
                 {"reloads", reloads_}};
  s["preview_clients"] = previewSinks_.size();
  s["event_clients"] = eventSinks_.size();
  if (!config_.hubUrl.empty())
    s["hub"] = hubStatusJson();
  return s;
}

void Station::status(std::function<void(nlohmann::json)> done) {
  postToStrand([this, done = std::move(done)] { done(statusJson()); });
}

void Station::job(std::int64_t id, std::function<void(std::optional<nlohmann::json>)> done) {
  postToStrand([this, id, done = std::move(done)] {
    auto j = catalog_->job(id);
    if (!j)
      return done(std::nullopt);
    nlohmann::json out = jobJson(*j);
    if (auto f = unrecordedFailures_.find(id);
        f != unrecordedFailures_.end() && out.value("state", "") != "done") {
      out["state"] = "failed";
      out["error"] = f->second;
    }
    done(out);
  });
}

void Station::broadcast(const std::string& event, const nlohmann::json& data) {
  std::string chunk = event.empty() ? std::string(": keep-alive\n\n")
                                    : "event: " + event + "\ndata: " + data.dump() + "\n\n";
  auto& sinks = eventSinks_;
  sinks.erase(std::remove_if(sinks.begin(), sinks.end(),
                             [&](const std::weak_ptr<StreamSink>& w) {
                               auto s = w.lock();
                               if (!s || !s->open())
                                 return true;
                               s->write(chunk);
                               return false;
                             }),
              sinks.end());
}

void Station::addEventSink(std::shared_ptr<StreamSink> sink) {
  postToStrand([this, sink] {
    Response head{http::status::ok, 11};
    head.set(http::field::content_type, "text/event-stream");
    head.set(http::field::cache_control, "no-store");
    sink->writeHeader(std::move(head));
    sink->write("retry: 2000\n\nevent: status\ndata: " + statusJson().dump() + "\n\n");
    eventSinks_.push_back(sink);
  });
}

// --- MJPEG preview -------------------------------------------------------------------------------

void Station::addPreviewSink(std::shared_ptr<StreamSink> sink) {
  postToStrand([this, sink] {
    Response head{http::status::ok, 11};
    head.set(http::field::content_type, "multipart/x-mixed-replace;boundary=garmcapframe");
    head.set(http::field::cache_control, "no-store, no-cache, must-revalidate");
    head.set(http::field::pragma, "no-cache");
    sink->writeHeader(std::move(head));
    const bool first = previewSinks_.empty();
    previewSinks_.push_back(sink);
    if (first)
      previewTick();
  });
}

void Station::previewTick() {
  previewSinks_.erase(std::remove_if(previewSinks_.begin(), previewSinks_.end(),
                                     [](const std::weak_ptr<StreamSink>& w) {
                                       auto s = w.lock();
                                       return !s || !s->open();
                                     }),
                      previewSinks_.end());
  if (previewSinks_.empty() || stopping_) {
    if (previewRunning_ && camera_) {
      previewRunning_ = false;
      asio::post(cameraThread_, [this] { camera_->stopPreview(); });
    }
    return;
  }
  // The camera thread is shared with stills: while one is taken the preview pauses; while the
  // pipeline works on it the preview goes on (staff dress the form for the next garment).
  if (!previewInFlight_ && !stillInFlight_ && cameraOpen_ && camera_) {
    previewInFlight_ = true;
    previewRunning_ = true;
    asio::post(cameraThread_, [this] {
      std::string jpeg;
      try {
        if (!camera_->previewRunning())
          camera_->startPreview();
        if (auto f = camera_->nextPreviewFrame(std::chrono::milliseconds(300))) {
          std::vector<unsigned char> buf;
          cv::imencode(".jpg", f->bgr, buf, {cv::IMWRITE_JPEG_QUALITY, 75});
          jpeg.assign(buf.begin(), buf.end());
        }
      } catch (const capture::CameraError& e) {
        spdlog::warn("station: preview frame failed: {}", e.what());
        if (e.kind() == capture::CameraErrorKind::kDisconnected ||
            e.kind() == capture::CameraErrorKind::kNotFound) {
          camera_->close();
          postToStrand([this, msg = std::string("camera: ") + e.what()] {
            cameraOpen_ = false;
            cameraError_ = msg;
            if (!running_ && !stopping_) {
              lastError_ = msg;
              setState(StationState::kError);
            }
            scheduleCameraRetry();
          });
        }
      } catch (const std::exception& e) {
        spdlog::warn("station: preview frame failed: {}", e.what());
      }
      postToStrand([this, jpeg = std::move(jpeg)] {
        previewInFlight_ = false;
        if (jpeg.empty())
          return;
        std::string part = "--garmcapframe\r\nContent-Type: image/jpeg\r\nContent-Length: " +
                           std::to_string(jpeg.size()) + "\r\n\r\n" + jpeg + "\r\n";
        for (auto& w : previewSinks_)
          if (auto s = w.lock())
            s->write(part);
      });
    });
  }
  previewTimer_.expires_after(std::chrono::milliseconds(200));
  previewTimer_.async_wait([this](boost::system::error_code ec) {
    if (!ec)
      previewTick();
  });
}

// --- lifecycle -----------------------------------------------------------------------------------

void Station::shutdown(std::chrono::seconds grace, std::function<void()> done) {
  postToStrand([this, grace, done = std::move(done)] {
    if (stopping_)
      return;
    stopping_ = true;
    shutdownDone_ = done;
    // Queued jobs stay queued in the catalog (checkpointed): the next start runs them, within
    // resume_queued_s. With resuming off they are cancelled now, so none is left dangling.
    for (const auto& p : queue_) {
      if (config_.resumeQueuedS > 0) {
        spdlog::info("station: job {} stays queued for the next start", p.jobId);
        continue;
      }
      try {
        catalog_->failJob(p.jobId, "cancelled: garmcapd stopped before the job started");
      } catch (const std::exception& e) {
        spdlog::error("station: {}", e.what());
      }
    }
    queue_.clear();
    setState(StationState::kStopping);
    if (running_) {
      spdlog::info("station: stopping after job {} finishes (at most {} s)",
                   running_->request.jobId, grace.count());
      graceTimer_.expires_after(grace);
      graceTimer_.async_wait([this](boost::system::error_code ec) {
        if (ec || !running_)
          return;
        const auto id = running_->request.jobId;
        try {
          catalog_->failJob(id, "interrupted: garmcapd stopped during " + running_->stage);
        } catch (const std::exception& e) {
          spdlog::error("station: {}", e.what());
        }
        running_.reset();
        maybeFinishShutdown();
      });
    }
    maybeFinishShutdown();
  });
}

void Station::maybeFinishShutdown() {
  if (!stopping_ || running_ || !shutdownDone_)
    return;
  ledTimer_.cancel();
  buttonTimer_.cancel();
  previewTimer_.cancel();
  keepAliveTimer_.cancel();
  graceTimer_.cancel();
  cameraRetryTimer_.cancel();
  if (buttonDescriptor_)
    static_cast<asio::posix::stream_descriptor*>(buttonDescriptor_.get())->cancel();
  for (auto& w : eventSinks_)
    if (auto s = w.lock())
      s->close();
  for (auto& w : previewSinks_)
    if (auto s = w.lock())
      s->close();
  if (gpio_ && gpio_->statusLed()) {
    try {
      gpio_->statusLed()->set(false);
    } catch (const std::exception&) {
    }
  }
  auto done = std::move(shutdownDone_);
  shutdownDone_ = nullptr;
  done();
}

void Station::loadShopSettings() {
  std::lock_guard lock(shopMutex_);
  shop_ = config_.shop;
  try {
    const auto saved = catalog_->setting("shop");
    if (!saved)
      return;
    ShopConfig shop = config_.shop;
    applyShopSettings(*saved, shop);
    savedShop_ = *saved;
    shop_ = shop;
  } catch (const std::exception& e) {
    // The station still captures; the exports fall back on the config file until the shop
    // saves its settings again.
    spdlog::error("station: the shop settings saved in the catalog are ignored: {}", e.what());
  }
}

ShopConfig Station::shopConfig() const {
  std::lock_guard lock(shopMutex_);
  return shop_;
}

nlohmann::json Station::savedShopSettings() const {
  std::lock_guard lock(shopMutex_);
  return savedShop_;
}

ShopConfig Station::saveShopSettings(Catalog& catalog, const nlohmann::json& changes) {
  if (!changes.is_object())
    throw BadRequest("the shop settings must be a JSON object of [shop] keys");
  nlohmann::json saved = savedShopSettings();
  for (const auto& [key, value] : changes.items())
    saved[key] = value;
  ShopConfig shop;
  {
    std::lock_guard lock(shopMutex_);
    shop = config_.shop;
  }
  try {
    applyShopSettings(saved, shop);
  } catch (const ConfigError& e) {
    throw BadRequest(e.what());
  }
  catalog.setSetting("shop", saved);
  std::lock_guard lock(shopMutex_);
  savedShop_ = std::move(saved);
  shop_ = shop;
  return shop;
}

void Station::reload(const Config& c) {
  postToStrand([this, c] {
    config_.reviewBelowConfidence = c.reviewBelowConfidence;
    config_.namingTemplate = c.namingTemplate;
    {
      std::lock_guard lock(shopMutex_);
      config_.shop = c.shop;
      shop_ = c.shop;
      try {
        applyShopSettings(savedShop_, shop_);
      } catch (const ConfigError& e) {  // checked when saved: only a hand-edited catalog
        spdlog::error("station: the saved shop settings are ignored: {}", e.what());
        shop_ = c.shop;
      }
    }
    config_.queueLimit = c.queueLimit;
    config_.makeProductImages = c.makeProductImages;
    config_.makeTexture = c.makeTexture;
    config_.productSizePx = c.productSizePx;
    config_.sizeChart = c.sizeChart;
    config_.resumeQueuedS = c.resumeQueuedS;
    config_.keepDeletedDays = c.keepDeletedDays;
    config_.keepFailedFramesDays = c.keepFailedFramesDays;
    for (const auto& key : restartOnlyChanges(config_, c))
      spdlog::warn("station: {} changed in the configuration; it takes effect after a restart",
                   key);
    ++reloads_;
    if (processorFactory_) {
      pendingProcessor_ = c;
      startNext();  // swaps the processor now when idle, else when the job in hand ends
    }
    spdlog::info("station: configuration reloaded");
  });
}

bool Station::healthy() const {
  const auto now = Clock::now();
  if (now - lastLoopTick_ > std::chrono::seconds(5))
    return false;  // the loop is stuck
  if (running_) {
    const auto inStage = now - running_->stageSince;
    if (running_->stage == "capturing" &&
        inStage > std::chrono::milliseconds(3 * config_.captureTimeoutMs) + std::chrono::seconds(5))
      return false;  // the camera thread hangs
    if (inStage > std::chrono::minutes(10))
      return false;  // a pipeline stage hangs
  }
  return true;
}

std::string Station::statusLine() const {
  std::string s = toString(state_);
  if (running_)
    s += " job " + std::to_string(running_->request.jobId) + " " + running_->stage;
  if (!queue_.empty())
    s += ", " + std::to_string(queue_.size()) + " queued";
  if (!lastError_.empty())
    s += "; last error: " + lastError_;
  return s;
}

void Station::withCatalog(std::function<void(Catalog&)> fn, Reply failed) {
  postToStrand([this, fn = std::move(fn), failed = std::move(failed)] {
    try {
      fn(*catalog_);
    } catch (...) {
      replyFailure(failed, "catalog task", std::current_exception());
    }
  });
}

void Station::offload(std::function<void()> fn, Reply failed) {
  asio::post(*servePool_, [fn = std::move(fn), failed = std::move(failed)] {
    try {
      fn();
    } catch (...) {
      replyFailure(failed, "worker task", std::current_exception());
    }
  });
}

}  // namespace garmcap::daemon
