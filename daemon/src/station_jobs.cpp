// The station's jobs: the queue's next job through the camera thread, the worker pool and back
// to the strand (bare-form calibration, dressed capture, re-run), and what a job leaves behind.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <boost/asio/post.hpp>
#include <chrono>
#include <exception>
#include <map>
#include <opencv2/core/utility.hpp>
#include <utility>
#include <vector>

#include "garmcap/capture/camera.h"
#include "garmcap/daemon/disk_full.h"
#include "garmcap/daemon/review_policy.h"
#include "garmcap/daemon/station.h"
#include "garmcap/daemon/tape.h"
#include "garmcap/pipeline/image_files.h"

namespace garmcap::daemon {

namespace asio = boost::asio;
using Clock = std::chrono::steady_clock;

namespace {

long long msBetween(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(b - a).count();
}

// The image kinds a back shot adds to an item (and a later back shot replaces): the still, the
// back photos and the ghost-mannequin front, with the WebP copies image_files.h makes.
const std::vector<std::string>& backShotKinds() {
  static const std::vector<std::string> kinds = {"back",
                                                 "cutout_back",
                                                 "product_back",
                                                 "product_back_webp",
                                                 "product_back_4x5",
                                                 "product_back_4x5_webp",
                                                 "product_ghost",
                                                 "product_ghost_webp",
                                                 "product_ghost_4x5",
                                                 "product_ghost_4x5_webp"};
  return kinds;
}

// A job's images encoded (image_files.h: side by side; or already, by the processor: `encoded`)
// and stored, in the order of `images` and of each kind's encodings. Blobs are durable before the
// transaction that names them (content_store.h); they are hashed, written and fsynced side by side
// too (a 12 MP overlay or cut-out takes a while), the store takes concurrent writers. Throws the
// first failure.
std::vector<ImageRef> storeImages(
    const ContentStore& store, const std::map<std::string, cv::Mat>& images,
    const std::shared_future<std::vector<pipeline::EncodedImage>>& encodedAlready = {}) {
  const std::vector<pipeline::EncodedImage> encoded =
      encodedAlready.valid() ? encodedAlready.get()
                             : pipeline::encodeImageSet({images.begin(), images.end()});
  std::vector<std::string> shas(encoded.size());
  std::vector<std::exception_ptr> failed(encoded.size());
  cv::parallel_for_(
      cv::Range(0, static_cast<int>(encoded.size())),
      [&](const cv::Range& r) {
        for (int i = r.start; i < r.end; ++i) {
          const auto at = static_cast<std::size_t>(i);
          try {
            shas[at] = store.put(encoded[at].bytes);
          } catch (...) {
            failed[at] = std::current_exception();
          }
        }
      },
      static_cast<double>(encoded.size()));
  std::vector<ImageRef> refs;
  for (std::size_t i = 0; i < encoded.size(); ++i) {
    if (failed[i])
      std::rethrow_exception(failed[i]);
    refs.push_back({encoded[i].kind, shas[i], encoded[i].mediaType,
                    static_cast<std::int64_t>(encoded[i].bytes.size())});
  }
  return refs;
}

}  // namespace

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
    const std::string mediaType = catalog_->imageMediaType(sha).value_or("image/png");
    if (!req.sku.size())
      req.sku = item->sku;
    running_->request = req;
    asio::post(*pool_, [this, req, sha, mediaType] {
      try {
        auto bytes = store_->read(sha);
        if (!bytes)
          throw std::runtime_error("the stored dressed frame " + sha + " is missing");
        cv::Mat frame = pipeline::decodeImageBytes(*bytes, "dressed frame");
        std::promise<StoredFrame> stored;  // a re-run's frame is stored and recorded already
        stored.set_value({sha, 0, false, mediaType});
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
  // A back shot shows the form wearing the garment too (turned round); a replay or synthetic
  // camera serves its dressed frame for it.
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
      if (req.kind == JobKind::kDressed) {
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
          stored->set_value(storeStill(req, frame, t0, t1));
        } catch (...) {
          stored->set_exception(std::current_exception());
        }
        postToStrand([this] { stillInFlight_ = false; });
        return;
      }
      StoredFrame still = storeStill(req, frame, t0, t1);
      postToStrand([this, req, bgr = frame.bgr, still = std::move(still)] {
        stillInFlight_ = false;
        cameraOpen_ = true;
        cameraError_.clear();
        onFrameStored(req, bgr, still);
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

Station::StoredFrame Station::storeStill(const Pending& req, const capture::Frame& frame,
                                         Clock::time_point taken, Clock::time_point arrived) {
  // A still the camera delivered encoded (its own JPEG, a replayed rig's file) is stored as it
  // came: its bytes decode to the frame the pipeline works on (capture::Frame::encoded), so a
  // re-run sees the same pixels, and no second encoding takes a core beside the pipeline. Any
  // other still is PNG at the fast setting (lossless).
  const bool asDelivered = !frame.encoded.empty() && (frame.encodedMediaType == "image/png" ||
                                                      frame.encodedMediaType == "image/jpeg");
  const std::string encodedHere = asDelivered ? std::string() : pipeline::encodePng(frame.bgr);
  const std::string& bytes = asDelivered ? frame.encoded : encodedHere;
  const auto encoded = Clock::now();
  StoredFrame out{store_->put(bytes), static_cast<std::int64_t>(bytes.size()), true,
                  asDelivered ? frame.encodedMediaType : "image/png"};
  spdlog::info("station: job {}: still {} ms, {} {} ms, stored {} ms", req.jobId,
               msBetween(taken, arrived), asDelivered ? "as delivered" : "PNG",
               msBetween(arrived, encoded), msBetween(encoded, Clock::now()));
  return out;
}

void Station::onFrameStored(Pending req, cv::Mat frame, StoredFrame still) {
  try {
    catalog_->addImage(still.sha256, still.mediaType, still.bytes);
  } catch (const std::exception& e) {
    return failJob(req, std::string("cannot record the frame: ") + e.what(), false);
  }
  if (req.kind == JobKind::kBack)
    return runBack(std::move(req), std::move(frame), std::move(still));
  runEmpty(std::move(req), std::move(frame), std::move(still.sha256));
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
  cv::Mat empty = pipeline::decodeImageBytes(*bytes, "bare-form frame");
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
  const std::string emptyMediaType =
      catalog_->imageMediaType(cal->emptySha256).value_or("image/png");
  asio::post(*pool_, [this, req, dressed, stored, cal = *cal, threshold, corrections,
                      emptyMediaType] {
    try {
      const auto t0 = Clock::now();
      // The hang tag is read beside the pipeline (zbar is single-threaded). It scans only what
      // differs from the bare-form frame and is not green screen (hangTagScanImage: 0.1 s of
      // CPU at 12 MP instead of 0.4 s on the whole frame), so it waits for that frame, which the
      // first capture after a calibration decodes here; without it, it scans all but the screen.
      std::promise<cv::Mat> bareForTag;
      std::future<std::string> tag;
      if (req.sku.empty())
        tag = std::async(std::launch::async, [dressed, bare = bareForTag.get_future()]() mutable {
          cv::Mat frame;
          try {
            frame = bare.get();
          } catch (const std::exception&) {
            // The job fails over the bare frame anyway; the scan still finishes.
          }
          return decodeHangTagSku(dressed, frame);
        });
      cv::Mat empty;
      try {
        empty = bareFrame(cal);
      } catch (...) {
        bareForTag.set_exception(std::current_exception());
        throw;
      }
      bareForTag.set_value(empty);
      const auto t1 = Clock::now();
      auto progress = [this](const std::string& stage, double p) {
        postToStrand([this, stage, p] { setStage(stage, 0.2 + 0.7 * p, false); });
      };
      ProcessedCapture r = processor_->process(empty, dressed, cal.json, progress, corrections);
      const auto t2 = Clock::now();
      // Encoding and fsyncing the product images takes a noticeable moment at full resolution;
      // the hang tag's scan (about a second at 12 MP) goes on beside it and is waited for after.
      postToStrand([this] { setStage("store", 0.92, false); });
      std::vector<ImageRef> photos = storeImages(*store_, r.images, r.encodedImages);
      auto item = std::make_shared<NewItem>();
      item->sku = tag.valid() ? tag.get() : req.sku;
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
      item->needsReview = needsReview(r.confidence, threshold, r.warnings);
      for (ImageRef& ref : photos)
        item->images.push_back(std::move(ref));
      const StoredFrame frame = stored.get();  // throws what storing the still threw
      item->images.push_back({"dressed", frame.sha256, frame.mediaType, 0});
      item->images.push_back({"empty", cal.emptySha256, emptyMediaType, 0});
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
      catalog_->addImage(frame.sha256, frame.mediaType, frame.bytes);
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
      // Keep the original frames on the item; the re-run belongs to the new job. The back
      // shot's images stay too: a re-run of the front does not take the back again.
      if (auto before = catalog_->item(req.itemId))
        for (const ImageRef& im : before->images)
          if (std::find(backShotKinds().begin(), backShotKinds().end(), im.kind) !=
              backShotKinds().end())
            item->images.push_back(im);
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

void Station::runBack(Pending req, cv::Mat back, StoredFrame backStill) {
  auto cal = catalog_->latestCalibration();
  if (!cal)
    return failJob(req, "the station is not calibrated: capture the bare form first", false);
  auto item = catalog_->item(req.itemId);
  if (!item)
    return failJob(req, "item " + std::to_string(req.itemId) + " is gone", false);
  auto job = item->jobId ? catalog_->job(*item->jobId) : std::nullopt;
  if (!job || job->dressedSha256.empty())
    return failJob(req, "the item's capture job is gone", false);
  // The back still is this job's frame: a refused back shot keeps it for a look, as a failed
  // capture keeps its still (and the [storage] retention lets it go alike).
  try {
    catalog_->setJobFrames(req.jobId, cal->emptySha256, backStill.sha256);
  } catch (const std::exception& e) {
    return failJob(req, std::string("cannot record the frame: ") + e.what(), false);
  }
  setState(StationState::kProcessing);
  setStage("back shot", 0.2, true);
  asio::post(*pool_, [this, req, back, backStill, cal = *cal, dressedSha = job->dressedSha256] {
    try {
      auto bytes = store_->read(dressedSha);
      if (!bytes)
        throw std::runtime_error("the stored dressed frame " + dressedSha + " is missing");
      const cv::Mat dressed = pipeline::decodeImageBytes(*bytes, "dressed frame");
      const cv::Mat empty = bareFrame(cal);
      auto progress = [this](const std::string& stage, double p) {
        postToStrand([this, stage, p] { setStage(stage, 0.2 + 0.7 * p, false); });
      };
      ProcessedCapture r = processor_->processBack(empty, dressed, back, cal.json, progress);
      postToStrand([this] { setStage("store", 0.92, false); });
      auto images = std::make_shared<std::vector<ImageRef>>(storeImages(*store_, r.images));
      images->push_back({"back", backStill.sha256, backStill.mediaType, backStill.bytes});
      // Not filed: the item's result.json stays the front's (docs/api.md); the log has them.
      spdlog::info("station: job {}: {}", req.jobId, r.result.dump());
      for (const auto& w : r.warnings)
        spdlog::warn("station: job {}: {}", req.jobId, w);
      postToStrand([this, req, images, calId = cal.id] {
        try {
          setStage("filing", 0.95, false);
          for (auto& sha :
               catalog_->addItemImages(req.itemId, backShotKinds(), *images, req.jobId, calId))
            reclaimCandidates_.push_back(std::move(sha));
          lastError_.clear();
          spdlog::info("station: job {} added the back shot's {} images to item {}", req.jobId,
                       images->size(), req.itemId);
        } catch (const std::exception& e) {
          return failJob(req, std::string("cannot file the back shot: ") + e.what(), false);
        }
        finishJob();
      });
    } catch (const std::exception& e) {
      postToStrand([this, req, msg = std::string(e.what())] { failJob(req, msg, false); });
    }
  });
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

}  // namespace garmcap::daemon
