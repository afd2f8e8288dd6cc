#include "garmcap/daemon/station.h"

#include <spdlog/spdlog.h>

#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/post.hpp>
#include <filesystem>
#include <thread>
#include <utility>

#include "garmcap/capture/camera.h"
#include "garmcap/capture/gpio.h"
#include "garmcap/daemon/disk_full.h"
#include "garmcap/daemon/unpluggable_camera.h"
#include "garmcap/pipeline/image_files.h"

namespace garmcap::daemon {

namespace asio = boost::asio;
using Clock = std::chrono::steady_clock;

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
    case JobKind::kBack:
      return "back";
  }
  return "?";
}

namespace {

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
      markerMaxPieces_(std::make_shared<std::atomic<int>>(config_.markerMaxPieces)),
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
  if (!pipeline::canWriteWebp())
    spdlog::warn("station: this OpenCV cannot write WebP; product photos are stored as JPEG only");
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
    else if (j.kind == toString(JobKind::kBack))
      p.kind = JobKind::kBack;
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
  // A re-run and a back shot both work on the item's stored dressed frame.
  const bool onItem = kind == JobKind::kRerun || kind == JobKind::kBack;
  if (onItem) {
    auto item = catalog_->item(itemId);
    if (!item)
      return answer({std::nullopt, 404, "no item " + std::to_string(itemId), false});
    auto job = item->jobId ? catalog_->job(*item->jobId) : std::nullopt;
    if (!job || job->dressedSha256.empty() || !store_->contains(job->dressedSha256))
      return answer({std::nullopt, 409,
                     "item " + std::to_string(itemId) + " has no stored dressed frame to " +
                         (kind == JobKind::kBack ? "take a back shot for" : "re-run"),
                     false});
    if (!calibrated_)
      return answer({std::nullopt, 409, "the station is not calibrated", false});
  }
  std::int64_t jobId = 0;
  try {
    jobId = catalog_->addJob(toString(kind), sku, onItem ? std::optional(itemId) : std::nullopt);
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
    config_.markerMaxPieces = c.markerMaxPieces;
    markerMaxPieces_->store(c.markerMaxPieces);
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
    config_.productShadow = c.productShadow;
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
