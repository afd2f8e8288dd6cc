#pragma once
// The station: state machine, capture queue, camera thread, worker pool, catalog owner.
//
//   uncalibrated --press/capture-empty--> capturing --> processing --> ready
//   ready --press/capture--> capturing --> processing --> ready          (item filed)
//   any job failure -> back to ready/uncalibrated with last_error; a camera failure -> error
//   (the next capture tries to reconnect). SIGTERM -> stopping: the job in hand finishes, queued
//   ones stay queued in the catalog, then the loop stops. At start-up a job left running (crash,
//   power loss) is marked failed; queued ones younger than Config::resumeQueuedS are run.
//
// Threads: every member function runs on the state strand (the public ones post themselves
// there, so they may be called from anywhere); the camera is used only on the camera thread,
// CaptureProcessor only on the worker pool. Results come back by posting to the strand.
// Presses while a job runs are queued; several presses before the queued one starts are merged
// into it (never lost, never multiplied). Queue length is bounded by Config::queueLimit.

#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/thread_pool.hpp>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "garmcap/daemon/capture_processor.h"
#include "garmcap/daemon/catalog.h"
#include "garmcap/daemon/config.h"
#include "garmcap/daemon/content_store.h"
#include "garmcap/daemon/http_router.h"

namespace garmcap::capture {
class Camera;
class Gpio;
struct Frame;
}  // namespace garmcap::capture

namespace garmcap::daemon {

enum class StationState { kUncalibrated, kReady, kCapturing, kProcessing, kError, kStopping };
const char* toString(StationState state);

/// Status LED pattern: bit i (0..7) says whether the LED is on during the i-th 125 ms tick of
/// each second. uncalibrated: slow blink; ready: steady; capturing: fast flicker; processing:
/// 2 Hz blink; error: double flash; stopping: off.
std::uint8_t ledPattern(StationState state);

// kBack: the back shot of a filed item (the garment turned back to front): a still, then the
// pipeline on the item's stored dressed frame with it, adding the back and ghost photos.
enum class JobKind { kEmpty, kDressed, kRerun, kBack };
const char* toString(JobKind kind);

/// Answer to a capture submission.
struct SubmitResult {
  std::optional<std::int64_t> jobId;
  int httpStatus =
      202;  // 202 accepted, 404 unknown item, 409 not calibrated, 503 queue full/stopping
  std::string error;
  bool merged = false;  // a button press merged into an already queued press
};

class Station : public RouteContext {
 public:
  Station(boost::asio::io_context& io, Config config, std::unique_ptr<capture::Camera> camera,
          std::unique_ptr<capture::Gpio> gpio, std::unique_ptr<CaptureProcessor> processor);
  ~Station() override;

  /// Opens the catalog and store, fails interrupted jobs, sweeps orphan blobs, opens the camera
  /// (an absent camera is an error state, not a start-up failure) and starts GPIO and timers.
  /// Throws on catalog/store errors. Call before io.run().
  void start();

  /// Capture requests. `done` runs on the strand.
  void submit(JobKind kind, std::string sku, std::int64_t itemId,
              std::function<void(SubmitResult)> done);
  /// A (simulated or GPIO) short press: bare-form capture when uncalibrated, else a garment.
  void press(std::function<void(SubmitResult)> done = {});
  /// A long press: always a bare-form capture (recalibration).
  void longPress();

  /// Station status JSON (docs/api.md); `done` runs on the strand.
  void status(std::function<void(nlohmann::json)> done);
  /// A job with live stage/progress for the running one.
  void job(std::int64_t id, std::function<void(std::optional<nlohmann::json>)> done);

  /// Server-sent events and MJPEG preview subscribers.
  void addEventSink(std::shared_ptr<StreamSink> sink);
  void addPreviewSink(std::shared_ptr<StreamSink> sink);

  /// SIGTERM: finish the job in hand (at most `grace`, then it is marked interrupted), leave the
  /// queued ones queued for the next start (cancelled when resuming is off), then `done`.
  void shutdown(std::chrono::seconds grace, std::function<void()> done);
  /// SIGHUP: applies the reloadable parts of a new, already validated config (pipeline options,
  /// naming, review threshold, queue limit, resume window); the processor is rebuilt at once when
  /// idle, else when the job in hand ends. Camera, GPIO, HTTP and data settings need a restart
  /// (each changed one is logged).
  void reload(const Config& config);

  /// Lets reload() rebuild the processor with new pipeline options (garmcapd sets it).
  /// With [hub] url: what the pusher reports (thread-safe), shown in /api/status under "hub".
  void setHubStatus(std::function<nlohmann::json()> f) { hubStatus_ = std::move(f); }
  void setProcessorFactory(std::function<std::unique_ptr<CaptureProcessor>(const Config&)> f) {
    processorFactory_ = std::move(f);
  }

  /// Before start(): the camera could not be created; the station runs in the error state and
  /// reports `reason` for every capture.
  void setCameraUnavailable(std::string reason) { cameraError_ = std::move(reason); }

  /// For the systemd watchdog: loop alive and no stage stuck beyond its limit.
  bool healthy() const;
  std::string statusLine() const;  // one line for STATUS=
  StationState state() const { return state_; }

  // RouteContext
  void withCatalog(std::function<void(Catalog&)> fn, Reply failed) override;
  void offload(std::function<void()> fn, Reply failed) override;
  const ContentStore& store() const override { return *store_; }
  std::string namingTemplate() const override { return config_.namingTemplate; }
  int markerMaxPieces() const override { return markerMaxPieces_->load(); }
  ShopConfig shopConfig() const override;
  nlohmann::json savedShopSettings() const override;
  ShopConfig saveShopSettings(Catalog& catalog, const nlohmann::json& changes) override;

  /// Simulated rig only: makes the camera "disappear" (every camera call fails as disconnected)
  /// or come back. Returns false when the station is not simulated.
  bool setCameraUnplugged(bool unplugged);
  /// Simulated rig only: each still takes `delay` before the camera answers (0: at once); an
  /// unplug during it fails the still as disconnected. Returns false when not simulated.
  bool setSimulatedStillDelay(std::chrono::milliseconds delay);
  bool simulated() const;
#ifdef GARMCAP_TEST_HOOKS
  /// Test builds only (GARMCAP_TEST_HOOKS): blocks the event loop for `duration`, then calls
  /// `done` on it, so that the e2e tests can see the systemd watchdog pings stop.
  void stallLoopForTest(std::chrono::milliseconds duration, std::function<void()> done);
#endif

 private:
  cv::Mat bareFrame(const Calibration& cal);  // decoded once per calibration
  // The setup screen's saved shop settings over the config's [shop] (start-up).
  void loadShopSettings();
  struct Pending {
    JobKind kind;
    std::int64_t jobId;
    std::string sku;
    std::int64_t itemId = 0;
    bool fromButton = false;
    int presses = 1;
  };
  struct Running {
    Pending request;
    std::string stage;
    double progress = 0;
    std::chrono::steady_clock::time_point stageSince;
  };

  void submitOnStrand(JobKind kind, std::string sku, std::int64_t itemId, bool fromButton,
                      std::function<void(SubmitResult)> done);
  void startNext();
  void setState(StationState s);
  void setStage(const std::string& stage, double progress, bool persist);
  struct StoredFrame {
    std::string sha256;
    std::int64_t bytes = 0;
    bool toRecord = true;  // its images row is still to be written (false: a re-run's frame)
    std::string mediaType = "image/png";
  };
  // On the camera thread: the still put in the store, as the camera delivered it when it came
  // encoded (capture::Frame::encoded), else as PNG. Throws what the store throws.
  StoredFrame storeStill(const Pending& req, const capture::Frame& frame,
                         std::chrono::steady_clock::time_point taken,
                         std::chrono::steady_clock::time_point arrived);
  void onFrameStored(Pending req, cv::Mat frame, StoredFrame still);
  void runEmpty(Pending req, cv::Mat frame, std::string sha);
  void runDressed(Pending req, cv::Mat dressed, std::shared_future<StoredFrame> stored);
  // On the strand: the still's images row and the job's frames; false (the job failed) if not.
  bool recordFrame(const Pending& req, const std::string& emptySha, const StoredFrame& frame);
  void onCalibrated(Pending req, std::string emptySha, nlohmann::json calibration);
  void onProcessed(Pending req, std::shared_ptr<NewItem> item);
  // The back shot's still stored and recorded: the pipeline on the item's dressed frame with it.
  void runBack(Pending req, cv::Mat back, StoredFrame backStill);
  void failJob(const Pending& req, const std::string& error, bool cameraFault);
  void finishJob();
  // On the strand, with no job in hand (a job puts its blobs before the row that names them, so
  // one it is about to name could look unreferenced): drops the image rows and files of blobs no
  // row needs any more among `candidates`, or among all when nullopt; hourly and at start-up also
  // purges what the [storage] retention lets go (deleted items, failed captures' frames).
  void reclaimStorage(std::optional<std::vector<std::string>> candidates);
  void broadcast(const std::string& event, const nlohmann::json& data);
  nlohmann::json jobJson(const Job& job) const;
  nlohmann::json statusJson();
  nlohmann::json hubStatusJson();
  void openCamera();
  // While the camera is away: open it again after 0.5, 1, 2, 4, then every 5 s, and go back to
  // ready by itself when it answers (the UI follows the state events).
  void scheduleCameraRetry();
  void startGpio();
  void armButtonTimer();
  void waitButton();
  void ledTick();
  void previewTick();
  void keepAliveTick();
  void maybeFinishShutdown();

  // Runs `f` on the strand unless the station is gone by then: the camera thread and the pool
  // post their results back, and an io_context that outlives the station (a restart in the same
  // process, the tests) would otherwise run them on a destroyed object.
  template <typename F>
  void postToStrand(F&& f) {
    boost::asio::post(strand_,
                      [life = std::weak_ptr<void>(alive_), f = std::forward<F>(f)]() mutable {
                        if (life.lock())
                          f();
                      });
  }

  std::shared_ptr<void> alive_ = std::make_shared<int>(0);
  boost::asio::io_context& io_;
  boost::asio::strand<boost::asio::io_context::executor_type> strand_;
  Config config_;
  std::unique_ptr<capture::Camera> camera_;
  std::unique_ptr<capture::Gpio> gpio_;
  std::unique_ptr<CaptureProcessor> processor_;
  std::function<std::unique_ptr<CaptureProcessor>(const Config&)> processorFactory_;
  std::function<nlohmann::json()> hubStatus_;
  std::optional<Config> pendingProcessor_;  // a reload's pipeline options, applied when idle
  int reloads_ = 0;
  std::unique_ptr<Catalog> catalog_;
  std::unique_ptr<ContentStore> store_;
  // The shop's setup-screen settings and the settings in force, read by export handlers on
  // other threads while the strand saves or reloads them.
  mutable std::mutex shopMutex_;
  nlohmann::json savedShop_ = nlohmann::json::object();
  ShopConfig shop_;
  boost::asio::thread_pool cameraThread_{1};
  std::unique_ptr<boost::asio::thread_pool> pool_;       // the pipeline
  std::unique_ptr<boost::asio::thread_pool> servePool_;  // RouteContext::offload

  StationState state_ = StationState::kUncalibrated;
  bool calibrated_ = false;
  std::optional<std::int64_t> calibrationId_;
  std::deque<Pending> queue_;
  std::optional<Running> running_;
  std::vector<std::string> reclaimCandidates_;  // blobs a re-run replaced, reclaimed when idle
  std::optional<std::chrono::steady_clock::time_point> lastRetentionPurge_;
  std::string lastError_;
  std::string readOnly_;  // why the station runs read-only (a full disk at start), or empty
  std::map<std::int64_t, std::string> unrecordedFailures_;  // job id -> reason (catalog unwritable)
  std::string cameraError_;
  bool cameraOpen_ = false;
  std::shared_ptr<std::atomic<bool>> unplugged_;
  std::shared_ptr<std::atomic<int>> stillDelayMs_;
  // [marker] max_pieces: read on the worker pool by the marker routes, set on reload.
  std::shared_ptr<std::atomic<int>> markerMaxPieces_;
  std::vector<std::weak_ptr<StreamSink>> eventSinks_;
  std::vector<std::weak_ptr<StreamSink>> previewSinks_;
  bool previewInFlight_ = false;
  bool stillInFlight_ = false;
  std::mutex bareFrameMutex_;  // the worker pool may hold more than one thread
  std::string bareFrameSha_;
  cv::Mat bareFrame_;  // the camera thread is taking (and storing) a still
  bool previewRunning_ = false;
  bool stopping_ = false;
  std::function<void()> shutdownDone_;
  int ledTick_ = 0;
  std::shared_ptr<void> buttonDescriptor_;  // posix::stream_descriptor, released on destruction
  boost::asio::steady_timer ledTimer_;
  boost::asio::steady_timer buttonTimer_;
  boost::asio::steady_timer previewTimer_;
  boost::asio::steady_timer keepAliveTimer_;
  boost::asio::steady_timer graceTimer_;
  boost::asio::steady_timer cameraRetryTimer_;
  std::chrono::milliseconds cameraRetryDelay_{0};
  bool cameraRetryPending_ = false;
  std::chrono::steady_clock::time_point lastLoopTick_;
};

}  // namespace garmcap::daemon
