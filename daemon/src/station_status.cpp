// What the station tells its clients: status and job JSON, the server-sent event stream and
// the camera's MJPEG preview.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <boost/asio/post.hpp>
#include <opencv2/imgcodecs.hpp>

#include "garmcap/capture/camera.h"
#include "garmcap/capture/gpio.h"
#include "garmcap/daemon/station.h"

namespace garmcap::daemon {

namespace asio = boost::asio;

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
                 {"product_shadow", config_.productShadow},
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

}  // namespace garmcap::daemon
