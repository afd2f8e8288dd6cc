#pragma once
// garmcapd configuration: a TOML file (toml11), then command-line flags on top. Every key is
// documented in docs/daemon.md. Reading is strict: an unknown key, a wrong type or a value out of
// range throws ConfigError naming the file, the key and the reason, and garmcapd refuses to start
// (on SIGHUP the running config is kept and the error logged).

#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace garmcap::daemon {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// [shop]: what the shop exports need to know about the shop (docs/exports.md).
struct ShopConfig {
  std::string brand;          // the label's or the shop's name (Merchant brand, Shopify vendor)
  std::string storeUrl;       // the shop's public address; product links are built on it
  std::string publicBaseUrl;  // where the exported images are published
  std::string storePlatform = "shopify";  // shopify | woocommerce: whose product links
  std::string currency = "EUR";           // ISO 4217
  std::string sizeSystem;                 // Merchant size_system; "" = none (e.g. Korean sizes)
  std::map<std::string, std::string> sizeLabels;  // chart size -> shop label, e.g. "55" = "S"
  bool madeToOrder = false;    // offer the graded run's other sizes as made-to-order variants
  bool allowLoopback = false;  // allow links to this machine (a shop served from this host)
};

struct Config {
  // [camera]
  std::string cameraBackend = "v4l2";  // libcamera | v4l2 | replay | synthetic
  std::string cameraDevice;            // /dev/video0, camera id, rig folder
  std::string formPath;                // dress-form sidecar (synthetic camera, calibration)
  int stillWidth = 0;                  // 0 = largest the device offers
  int stillHeight = 0;
  int captureTimeoutMs = 5000;
  // [gpio]
  std::string gpioBackend = "gpiod";  // gpiod | simulated
  std::string buttonChip;             // chip label or name, "" = search all
  std::string buttonLine = "GPIO17";
  bool buttonActiveLow = true;
  std::string ledChip;
  std::string ledLine;  // "" = no LED fitted
  int debounceMs = 30;
  int longPressMs = 2000;
  // [paths]
  std::string dataDir = "/var/lib/garmcapd";
  std::string webDir;  // "" = compiled-in GARMCAP_WEB_DIR
  // [http]
  std::string listenAddress = "127.0.0.1";
  std::uint16_t listenPort = 8080;
  std::string token;  // bearer token; required when the address is not loopback
  std::size_t bodyLimitBytes = 1 << 20;
  int requestTimeoutS = 30;  // a request's body; a response gets this plus 1 s per minSendRate
  // Bytes per second: a response (or a download's piece) must be written within
  // requestTimeoutS + its size / minSendRate, or its connection is closed (writeDeadline).
  std::size_t minSendRate = 32 * 1024;
  int headerTimeoutS = 10;  // a request's header, counted from the connection or last answer
  int maxConnections = 256;
  // Of those, what one client address may hold: a tablet's browser opens about six, plus the
  // event stream and the preview; a hub pusher one.
  int maxConnectionsPerClient = 32;
  // Host names the station answers to besides IP literals and "localhost" (a tablet's
  // "station.local"); requests for any other name are refused (DNS rebinding). garmcapd adds the
  // machine's own host name and <hostname>.local at start-up.
  std::vector<std::string> serverNames;
  // [pipeline]
  bool makeProductImages = true;
  bool makeTexture = true;
  int productSizePx = 4096;
  bool productShadow = false;  // a soft drop shadow on the white photos (docs/exports.md)
  std::string sizeChart = "korean_women";
  // [marker]
  int markerMaxPieces = 60;  // drafts::kDefaultMarkerMaxPieces: pieces one marker lays at most
  double reviewBelowConfidence = 0.8;  // items under this confidence wait for approval
  int workerThreads = 1;
  int queueLimit = 32;  // pending captures; more are refused with 503
  // Captures still queued when garmcapd stopped (SIGTERM, crash, power loss) are run when it
  // starts again within this many seconds of the request; older ones are failed as expired
  // (the garment is likely no longer on the form). 0: never resume.
  int resumeQueuedS = 600;
  // [storage]: how long what staff deleted and the frames of failed captures are kept before
  // their rows and image files are reclaimed (docs/daemon.md, "Storage"). 0: keep forever.
  int keepDeletedDays = 30;
  int keepFailedFramesDays = 14;
  // [naming]
  std::string namingTemplate = "{sku}_{kind}";
  // [shop]
  ShopConfig shop;
  // [hub]: the chain's hub this station pushes its catalog to (docs/hub.md); "" = none.
  std::string hubUrl;     // https://HOST:PORT, or http:// to a hub on loopback
  std::string hubToken;   // this station's token at the hub
  std::string hubCaFile;  // PEM CA certificate(s) for the hub's; "" = the system's store
  int hubPollMs = 2000;   // how often the outbox and the hub's edits are looked at

  /// Throws ConfigError if the combination is unsafe or incomplete (e.g. a non-loopback
  /// address without a token).
  void validate() const;
  bool loopbackOnly() const;
};

/// Applies shop settings saved from the web UI's setup screen (a JSON object with the [shop]
/// keys: "brand", "store_url", "size_labels": {"55": "S"}, "made_to_order": true, ...) over
/// `shop`, through the very checks the config file's [shop] section gets. Throws ConfigError
/// naming the key ("shop.currency: must be an ISO 4217 code ...") for an unknown key or a bad
/// value; `shop` is then unchanged.
void applyShopSettings(const nlohmann::json& settings, ShopConfig& shop);
/// The [shop] keys of `shop`, as applyShopSettings reads them.
nlohmann::json shopSettingsJson(const ShopConfig& shop);

/// Where [hub] url points: http://HOST:PORT or https://HOST:PORT (no path).
struct HubAddress {
  std::string host;
  std::uint16_t port = 0;
  bool tls = false;  // https: the hub's certificate is verified, with its host name
  std::string url() const {
    return (tls ? "https://" : "http://") + host + ":" + std::to_string(port);
  }
};
std::optional<HubAddress> parseHubUrl(const std::string& url);

/// Reads a TOML file over the defaults. Throws ConfigError ("<file>: [http] port: must be
/// 1..65535, got 0").
Config loadConfig(const std::filesystem::path& file, Config defaults = {});
/// The same on TOML text already read; `fileName` only names it in messages (the fuzzer feeds
/// text here without a file).
Config parseConfigText(const std::string& text, const std::string& fileName, Config defaults = {});
/// Parses "HOST:PORT" (IPv4 or [IPv6]) into the config; throws ConfigError naming `what`.
void parseListen(const std::string& text, Config& config, const std::string& what);
/// The simulated rig: synthetic camera on the shared dress form, simulated button.
void applySimulated(Config& config);

}  // namespace garmcap::daemon
