// garmcapd: the station daemon. Parses options, wires the objects, runs the event loop.
//   garmcapd --config /etc/garmcapd/garmcapd.toml
//   garmcapd --simulated --data DIR --listen 127.0.0.1:8080
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <systemd/sd-daemon.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <csignal>
#include <iostream>
#include <thread>

#include "garmcap/capture/camera.h"
#include "garmcap/capture/gpio.h"
#include "garmcap/daemon/config.h"
#include "garmcap/daemon/http_server.h"
#include "garmcap/daemon/hub_pusher.h"
#include "garmcap/daemon/station.h"
#include "garmcap/daemon/station_routes.h"
#include "garmcap/pipeline/capture_pipeline.h"
#include "garmcap/sim/synthetic_camera.h"

namespace asio = boost::asio;
using namespace garmcap;

namespace {

struct Options {
  std::string configFile;
  bool simulated = false;
  std::string data, listen, token, webDir, camera, device, form, logLevel = "info";
};

daemon::Config buildConfig(const Options& o) {
  daemon::Config c;
  if (!o.configFile.empty())
    c = daemon::loadConfig(o.configFile);
  if (o.simulated)
    daemon::applySimulated(c);
  if (!o.data.empty())
    c.dataDir = o.data;
  if (!o.listen.empty())
    daemon::parseListen(o.listen, c, "--listen");
  if (!o.token.empty())
    c.token = o.token;
  if (!o.webDir.empty())
    c.webDir = o.webDir;
  if (!o.camera.empty())
    c.cameraBackend = o.camera;
  if (!o.device.empty())
    c.cameraDevice = o.device;
  if (!o.form.empty())
    c.formPath = o.form;
  // systemd's StateDirectory= when no data folder was given explicitly.
  if (o.data.empty() && o.configFile.empty())
    if (const char* state = std::getenv("STATE_DIRECTORY"))
      c.dataDir = state;
  if (const char* t = std::getenv("GARMCAPD_TOKEN"); t && c.token.empty())
    c.token = t;
  // The machine's own names (what a tablet types, or finds over mDNS) are always the station's.
  char host[256] = {};
  if (gethostname(host, sizeof host - 1) == 0 && host[0] != '\0') {
    c.serverNames.push_back(host);
    c.serverNames.push_back(std::string(host) + ".local");
  }
  c.validate();
  return c;
}

std::unique_ptr<capture::Gpio> makeGpio(const daemon::Config& c) {
  capture::GpioConfig g;
  g.backend = c.gpioBackend == "simulated" ? "simulated" : "gpiod";
  g.button = {c.buttonChip, c.buttonLine, c.buttonActiveLow};
  if (!c.ledLine.empty())
    g.statusLed = capture::GpioLineSpec{c.ledChip, c.ledLine, false};
  g.debounce.stable = std::chrono::milliseconds(c.debounceMs);
  g.debounce.longPress = std::chrono::milliseconds(c.longPressMs);
  return capture::makeGpio(g);
}

}  // namespace

int main(int argc, char** argv) {
  garmcap::pipeline::keepFrameMemoryMapped();
  CLI::App app{"garmcapd: the GarmCap Station daemon (HTTP API, catalog, capture queue)"};
  Options o;
  app.add_option("-c,--config", o.configFile, "TOML configuration file")->check(CLI::ExistingFile);
  app.add_flag("--simulated", o.simulated, "simulated rig: synthetic camera, simulated button");
  app.add_option("--data", o.data, "station data folder (catalog, image store)");
  app.add_option("--listen", o.listen, "HTTP address HOST:PORT (default 127.0.0.1:8080)");
  app.add_option("--token", o.token, "bearer token (or env GARMCAPD_TOKEN)");
  app.add_option("--web-dir", o.webDir, "folder of the web UI");
  app.add_option("--camera", o.camera, "camera back end: libcamera, v4l2, replay, synthetic");
  app.add_option("--device", o.device, "camera device, camera id or rig folder");
  app.add_option("--form", o.form, "dress-form sidecar JSON (synthetic camera)");
  app.add_option("--log-level", o.logLevel, "trace, debug, info, warn, error");
  CLI11_PARSE(app, argc, argv);
  // Logs go to stderr (the journal under systemd); stdout carries only the "listening" line.
  spdlog::set_default_logger(spdlog::stderr_color_mt("garmcapd"));
  std::signal(SIGPIPE, SIG_IGN);
  spdlog::set_level(spdlog::level::from_str(o.logLevel));

  daemon::Config config;
  try {
    config = buildConfig(o);
  } catch (const std::exception& e) {
    std::cerr << "garmcapd: invalid configuration: " << e.what() << "\n";
    sd_notifyf(0, "STATUS=invalid configuration: %s", e.what());
    return 2;
  }

  asio::io_context io{1};
  std::unique_ptr<daemon::Station> station;
  std::unique_ptr<daemon::HttpServer> server;
  std::unique_ptr<daemon::HubPusher> pusher;  // with [hub] url: the chain's hub (docs/hub.md)
  daemon::Router router;
  std::unique_ptr<daemon::StaticFiles> files;
  try {
    capture::CameraOptions co;
    co.backend = config.cameraBackend;
    co.device = config.cameraDevice;
    co.formPath = config.formPath;
    // A camera that cannot even be created (back end not usable in this build) leaves the
    // station up in the error state with the reason, like an unplugged camera: the API, the
    // catalog and the web UI stay available.
    std::unique_ptr<capture::Camera> camera;
    std::string cameraProblem;
    try {
      camera = sim::makeCamera(co);  // the synthetic camera too (the simulated station)
    } catch (const capture::CameraError& e) {
      cameraProblem = e.what();
      spdlog::error("garmcapd: no camera: {}", cameraProblem);
    }
    std::unique_ptr<capture::Gpio> gpio = makeGpio(config);
    station = std::make_unique<daemon::Station>(io, config, std::move(camera), std::move(gpio),
                                                daemon::makePipelineProcessor(config));
    station->setProcessorFactory(
        [](const daemon::Config& c) { return daemon::makePipelineProcessor(c); });
    if (!cameraProblem.empty())
      station->setCameraUnavailable(cameraProblem);
    station->start();
    if (!config.hubUrl.empty()) {
      pusher = std::make_unique<daemon::HubPusher>(*station, config);
      station->setHubStatus([p = pusher.get()] { return p->status(); });
      pusher->start();
    }
    daemon::addStationRoutes(router, *station);
#ifdef GARMCAP_WEB_DIR
    const std::string webDir = config.webDir.empty() ? GARMCAP_WEB_DIR : config.webDir;
#else
    const std::string webDir = config.webDir;
#endif
    files = std::make_unique<daemon::StaticFiles>(webDir);
    server = std::make_unique<daemon::HttpServer>(io, config, router, *files);
    server->start();
  } catch (const std::exception& e) {
    std::cerr << "garmcapd: cannot start: " << e.what() << "\n";
    sd_notifyf(0, "STATUS=cannot start: %s", e.what());
    return 1;
  }
  spdlog::info("garmcapd: listening on http://{}:{}/ (data in {}{})", config.listenAddress,
               server->port(), config.dataDir, config.token.empty() ? "" : ", token required");
  // Tests read the port from here when they ask for port 0.
  std::cout << "garmcapd listening on " << config.listenAddress << ":" << server->port()
            << std::endl;

  // Signals: SIGTERM/SIGINT finish the job in hand and exit; SIGHUP reloads the config file.
  asio::signal_set signals(io, SIGTERM, SIGINT, SIGHUP);
  std::function<void()> waitSignal;
  bool stopping = false;
  waitSignal = [&] {
    signals.async_wait([&](boost::system::error_code ec, int sig) {
      if (ec)
        return;
      if (sig == SIGHUP) {
        sd_notify(0, "RELOADING=1");
        try {
          daemon::Config fresh = buildConfig(o);
          station->reload(fresh);
          files->rescan();
          spdlog::info("garmcapd: SIGHUP: configuration reloaded");
        } catch (const std::exception& e) {
          // The message names the file, the key and the reason (config.h).
          spdlog::error("garmcapd: reload refused, keeping the running config: {}", e.what());
        }
        sd_notify(0, "READY=1");
      } else if (!stopping) {
        stopping = true;
        spdlog::info("garmcapd: signal {}: stopping", sig);
        sd_notify(0, "STOPPING=1\nSTATUS=stopping: finishing the job in hand");
        server->stop();
        station->shutdown(std::chrono::seconds(60), [&io] { io.stop(); });
      } else {
        spdlog::warn("garmcapd: second signal: exiting now");
        io.stop();
      }
      waitSignal();
    });
  };
  waitSignal();

  // systemd watchdog: ping at half the interval, and only while the station is healthy, so a
  // hung camera or pipeline stage gets the service restarted.
  asio::steady_timer watchdog(io);
  std::uint64_t watchdogUsec = 0;
  std::function<void()> ping;
  std::string lastStatus;
  if (sd_watchdog_enabled(0, &watchdogUsec) > 0) {
    ping = [&] {
      if (station->healthy())
        sd_notify(0, "WATCHDOG=1");
      else
        spdlog::error("garmcapd: unhealthy ({}), withholding the watchdog ping",
                      station->statusLine());
      const std::string s = "STATUS=" + station->statusLine();
      if (s != lastStatus)
        sd_notify(0, s.c_str()), lastStatus = s;
      watchdog.expires_after(std::chrono::microseconds(watchdogUsec / 2));
      watchdog.async_wait([&](boost::system::error_code ec) {
        if (!ec)
          ping();
      });
    };
    ping();
  }
  const std::string ready = "READY=1\nSTATUS=" + station->statusLine();
  sd_notify(0, ready.c_str());

  // A handler that throws must not stop the station: the exception is logged and the loop goes
  // on (asio allows run() again after an exception). Handlers catch their own; this is the net.
  for (;;) {
    try {
      io.run();
      break;
    } catch (const std::exception& e) {
      spdlog::error("garmcapd: an event handler failed, serving on: {}", e.what());
    } catch (...) {
      spdlog::error("garmcapd: an event handler failed (non-standard exception), serving on");
    }
  }
  if (pusher)
    station->setHubStatus({});  // the status must not reach a pusher that is gone
  pusher.reset();               // before the station: it reaches the catalog through it
  server.reset();
  station.reset();
  spdlog::info("garmcapd: stopped");
  return 0;
}
