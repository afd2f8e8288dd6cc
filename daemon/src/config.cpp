#include "garmcap/daemon/config.h"

#include <arpa/inet.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <toml.hpp>

#include "garmcap/daemon/toml_input.h"
#include "garmcap/daemon/utf8.h"
#include "garmcap/drafts/size_charts.h"

namespace garmcap::daemon {

namespace {

using Setter = std::function<void(const toml::value&, Config&, const std::string& key)>;

[[noreturn]] void bad(const std::string& key, const std::string& reason) {
  throw ConfigError(key + ": " + reason);
}

Setter stringKey(std::string Config::*member) {
  return [member](const toml::value& v, Config& c, const std::string& key) {
    if (!v.is_string())
      bad(key, "must be a string");
    c.*member = v.as_string().str;
  };
}

Setter boolKey(bool Config::*member) {
  return [member](const toml::value& v, Config& c, const std::string& key) {
    if (!v.is_boolean())
      bad(key, "must be true or false");
    c.*member = v.as_boolean();
  };
}

template <typename Int>
Setter intKey(Int Config::*member, long long lo, long long hi) {
  return [member, lo, hi](const toml::value& v, Config& c, const std::string& key) {
    if (!v.is_integer())
      bad(key, "must be an integer");
    const long long x = v.as_integer();
    if (x < lo || x > hi)
      bad(key, "must be " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " +
                   std::to_string(x));
    c.*member = static_cast<Int>(x);
  };
}

Setter doubleKey(double Config::*member, double lo, double hi) {
  return [member, lo, hi](const toml::value& v, Config& c, const std::string& key) {
    double x = 0;
    if (v.is_floating())
      x = v.as_floating();
    else if (v.is_integer())
      x = static_cast<double>(v.as_integer());
    else
      bad(key, "must be a number");
    if (!(x >= lo && x <= hi)) {
      std::ostringstream msg;  // "[0, 1], got 2.5", not std::to_string's "0.000000"
      msg << "must be in [" << lo << ", " << hi << "], got " << x;
      bad(key, msg.str());
    }
    c.*member = x;
  };
}

Setter oneOf(std::string Config::*member, std::vector<std::string> allowed) {
  return [member, allowed](const toml::value& v, Config& c, const std::string& key) {
    if (!v.is_string())
      bad(key, "must be a string");
    const std::string s = v.as_string().str;
    if (std::find(allowed.begin(), allowed.end(), s) == allowed.end()) {
      std::string list;
      for (const auto& a : allowed)
        list += (list.empty() ? "" : ", ") + a;
      bad(key, "must be one of " + list + ", got '" + s + "'");
    }
    c.*member = s;
  };
}

Setter shopString(std::string ShopConfig::*member, std::size_t maxLen) {
  return [member, maxLen](const toml::value& v, Config& c, const std::string& key) {
    if (!v.is_string())
      bad(key, "must be a string");
    const std::string s = v.as_string().str;
    if (s.size() > maxLen)
      bad(key, "must be at most " + std::to_string(maxLen) + " bytes");
    for (unsigned char ch : s)
      if (ch < 32 || ch == 127)
        bad(key, "must not hold control characters");
    c.shop.*member = s;
  };
}

// A URL a shop fetches: http(s), printable ASCII without spaces or quotes ("" = not set).
Setter shopUrl(std::string ShopConfig::*member) {
  return [member](const toml::value& v, Config& c, const std::string& key) {
    if (!v.is_string())
      bad(key, "must be a string");
    const std::string s = v.as_string().str;
    if (!s.empty() && s.rfind("http://", 0) != 0 && s.rfind("https://", 0) != 0)
      bad(key, "must start with http:// or https://, got '" + s + "'");
    for (unsigned char ch : s)
      if (ch <= 32 || ch >= 127 || ch == '"' || ch == '\'' || ch == '<' || ch == '>' || ch == '\\')
        bad(key, "holds a character not allowed in a URL");
    c.shop.*member = s;
  };
}

Setter shopBool(bool ShopConfig::*member) {
  return [member](const toml::value& v, Config& c, const std::string& key) {
    if (!v.is_boolean())
      bad(key, "must be true or false");
    c.shop.*member = v.as_boolean();
  };
}

const std::map<std::string, std::map<std::string, Setter>>& schema() {
  static const std::map<std::string, std::map<std::string, Setter>> kSchema = {
      {"camera",
       // The names of capture::cameraBackends() and sim's "synthetic", spelled out: this file is in
       // garmcap::http, which the hub links without the camera or the simulator.
       {{"backend", oneOf(&Config::cameraBackend, {"libcamera", "v4l2", "replay", "synthetic"})},
        {"device", stringKey(&Config::cameraDevice)},
        {"form", stringKey(&Config::formPath)},
        {"still_width", intKey(&Config::stillWidth, 0, 16384)},
        {"still_height", intKey(&Config::stillHeight, 0, 16384)},
        {"capture_timeout_ms", intKey(&Config::captureTimeoutMs, 100, 600000)}}},
      {"gpio",
       {{"backend", oneOf(&Config::gpioBackend, {"gpiod", "simulated"})},
        {"button_chip", stringKey(&Config::buttonChip)},
        {"button_line", stringKey(&Config::buttonLine)},
        {"button_active_low", boolKey(&Config::buttonActiveLow)},
        {"led_chip", stringKey(&Config::ledChip)},
        {"led_line", stringKey(&Config::ledLine)},
        {"debounce_ms", intKey(&Config::debounceMs, 1, 1000)},
        {"long_press_ms", intKey(&Config::longPressMs, 200, 60000)}}},
      {"paths", {{"data", stringKey(&Config::dataDir)}, {"web_dir", stringKey(&Config::webDir)}}},
      {"http",
       {{"listen",
         [](const toml::value& v, Config& c, const std::string& key) {
           if (!v.is_string())
             bad(key, "must be a string \"HOST:PORT\"");
           parseListen(v.as_string().str, c, key);
         }},
        {"token", stringKey(&Config::token)},
        {"body_limit_bytes", intKey(&Config::bodyLimitBytes, 1024, 256LL << 20)},
        {"request_timeout_s", intKey(&Config::requestTimeoutS, 1, 3600)},
        {"min_send_rate", intKey(&Config::minSendRate, 1024, 1LL << 30)},
        {"header_timeout_s", intKey(&Config::headerTimeoutS, 1, 600)},
        {"max_connections", intKey(&Config::maxConnections, 1, 10000)},
        {"max_connections_per_client", intKey(&Config::maxConnectionsPerClient, 1, 10000)},
        {"server_names",
         [](const toml::value& v, Config& c, const std::string& key) {
           if (!v.is_array())
             bad(key, "must be an array of host names, e.g. [\"station.local\"]");
           std::vector<std::string> names;
           for (const auto& n : v.as_array()) {
             const std::string s = n.is_string() ? n.as_string().str : "";
             if (s.empty() || s.size() > 253 || !std::all_of(s.begin(), s.end(), [](char ch) {
                   return std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '.';
                 }))
               bad(key, "must hold host names (letters, digits, '-', '.')");
             names.push_back(s);
           }
           c.serverNames = names;
         }}}},
      {"pipeline",
       {{"product_images", boolKey(&Config::makeProductImages)},
        {"texture", boolKey(&Config::makeTexture)},
        {"product_size_px", intKey(&Config::productSizePx, 64, 8192)},
        {"product_shadow", boolKey(&Config::productShadow)},
        {"size_chart",
         [](const toml::value& v, Config& c, const std::string& key) {
           if (!v.is_string())
             bad(key, "must be a string");
           // Checked here, so that a mistyped chart is refused at start-up or at SIGHUP (and the
           // running one kept) instead of failing every capture after it.
           try {
             drafts::sizeChart(v.as_string().str);
           } catch (const std::invalid_argument& e) {
             bad(key, e.what());
           }
           c.sizeChart = v.as_string().str;
         }},
        {"review_below_confidence", doubleKey(&Config::reviewBelowConfidence, 0.0, 1.0)},
        {"worker_threads", intKey(&Config::workerThreads, 1, 64)},
        {"queue_limit", intKey(&Config::queueLimit, 1, 10000)},
        {"resume_queued_s", intKey(&Config::resumeQueuedS, 0, 7 * 86400)}}},
      {"storage",
       {{"keep_deleted_days", intKey(&Config::keepDeletedDays, 0, 3650)},
        {"keep_failed_frames_days", intKey(&Config::keepFailedFramesDays, 0, 3650)}}},
      {"naming", {{"template", stringKey(&Config::namingTemplate)}}},
      {"marker", {{"max_pieces", intKey(&Config::markerMaxPieces, 1, 1000)}}},
      {"shop",
       {{"brand", shopString(&ShopConfig::brand, 150)},
        {"store_url", shopUrl(&ShopConfig::storeUrl)},
        {"public_base_url", shopUrl(&ShopConfig::publicBaseUrl)},
        {"store_platform",
         [](const toml::value& v, Config& c, const std::string& key) {
           if (!v.is_string() ||
               (v.as_string().str != "shopify" && v.as_string().str != "woocommerce"))
             bad(key, "must be \"shopify\" or \"woocommerce\"");
           c.shop.storePlatform = v.as_string().str;
         }},
        {"currency",
         [](const toml::value& v, Config& c, const std::string& key) {
           const std::string s = v.is_string() ? v.as_string().str : "";
           if (s.size() != 3 ||
               !std::all_of(s.begin(), s.end(), [](char ch) { return ch >= 'A' && ch <= 'Z'; }))
             bad(key, "must be an ISO 4217 code of three capital letters, like \"EUR\"");
           c.shop.currency = s;
         }},
        {"size_system",
         [](const toml::value& v, Config& c, const std::string& key) {
           // Merchant Center's list; a chart that is none of them (Korean 44-88) sets none.
           static const std::vector<std::string> kSystems = {"",   "AU", "BR", "CN",  "DE", "EU",
                                                             "FR", "IT", "JP", "MEX", "UK", "US"};
           const std::string s = v.is_string() ? v.as_string().str : "?";
           if (std::find(kSystems.begin(), kSystems.end(), s) == kSystems.end())
             bad(key, "must be one of AU, BR, CN, DE, EU, FR, IT, JP, MEX, UK, US or \"\" (none)");
           c.shop.sizeSystem = s;
         }},
        {"size_labels",
         [](const toml::value& v, Config& c, const std::string& key) {
           if (!v.is_table())
             bad(key, "must be a table of chart size = \"label\", e.g. { \"55\" = \"S\" }");
           std::map<std::string, std::string> labels;
           for (const auto& [size, label] : v.as_table()) {
             if (!label.is_string() || label.as_string().str.empty() ||
                 label.as_string().str.size() > 32)
               bad(key + "." + size, "must be a label of 1..32 characters");
             labels[size] = label.as_string().str;
           }
           c.shop.sizeLabels = labels;
         }},
        {"made_to_order", shopBool(&ShopConfig::madeToOrder)},
        {"allow_loopback", shopBool(&ShopConfig::allowLoopback)}}},
      {"hub",
       {{"url",
         [](const toml::value& v, Config& c, const std::string& key) {
           const std::string s = v.is_string() ? v.as_string().str : "";
           if (!s.empty() && !parseHubUrl(s))
             bad(key,
                 "must be https://HOST:PORT or http://HOST:PORT with an IP address or name, "
                 "got '" +
                     quoteInput(s) + "'");
           c.hubUrl = s;
         }},
        {"token", stringKey(&Config::hubToken)},
        {"ca_file", stringKey(&Config::hubCaFile)},
        {"poll_ms", intKey(&Config::hubPollMs, 50, 600000)}}},
  };
  return kSchema;
}

bool isLoopback(const std::string& address) {
  in_addr a4{};
  if (inet_pton(AF_INET, address.c_str(), &a4) == 1)
    return (ntohl(a4.s_addr) >> 24) == 127;
  return address == "::1";
}

}  // namespace

void parseListen(const std::string& text, Config& c, const std::string& what) {
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0)
    throw ConfigError(what + ": expected HOST:PORT, got '" + text + "'");
  std::string host = text.substr(0, colon);
  const std::string port = text.substr(colon + 1);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']')
    host = host.substr(1, host.size() - 2);
  in_addr a4{};
  in6_addr a6{};
  if (inet_pton(AF_INET, host.c_str(), &a4) != 1 && inet_pton(AF_INET6, host.c_str(), &a6) != 1)
    throw ConfigError(what + ": '" + host + "' is not an IPv4 or IPv6 address");
  int p = 0;
  try {
    std::size_t used = 0;
    p = std::stoi(port, &used);
    if (used != port.size())
      p = -1;
  } catch (const std::exception&) {
    p = -1;
  }
  if (p < 0 || p > 65535)
    throw ConfigError(what + ": port must be 0..65535, got '" + port + "'");
  c.listenAddress = host;
  c.listenPort = static_cast<std::uint16_t>(p);
}

bool Config::loopbackOnly() const {
  return isLoopback(listenAddress);
}

void Config::validate() const {
  if (!loopbackOnly() && token.size() < 16)
    throw ConfigError(
        "[http] token: a token of at least 16 characters is required when "
        "listening on " +
        listenAddress + " (not a loopback address)");
  if (dataDir.empty())
    throw ConfigError("[paths] data: must not be empty");
  if (cameraBackend == "replay" && cameraDevice.empty())
    throw ConfigError("[camera] device: the replay back end needs the rig folder");
  if (gpioBackend == "gpiod" && buttonLine.empty())
    throw ConfigError("[gpio] button_line: required with the gpiod back end");
  if (namingTemplate.empty())
    throw ConfigError("[naming] template: must not be empty");
  if (!hubUrl.empty() && hubToken.empty())
    throw ConfigError("[hub] token: required with [hub] url (this station's token at the hub)");
  if (!hubCaFile.empty()) {
    const auto hub = parseHubUrl(hubUrl);
    if (!hub || !hub->tls)
      throw ConfigError("[hub] ca_file: only with an https:// [hub] url");
    if (!std::ifstream(hubCaFile, std::ios::binary))
      throw ConfigError(
          "[hub] ca_file: " + hubCaFile + ": " +
          (std::filesystem::exists(hubCaFile) ? "cannot be read (permissions?)" : "no such file"));
  }
}

std::optional<HubAddress> parseHubUrl(const std::string& url) {
  const bool tls = url.rfind("https://", 0) == 0;
  if (!tls && url.rfind("http://", 0) != 0)
    return std::nullopt;
  std::string rest = url.substr(tls ? 8 : 7);
  while (!rest.empty() && rest.back() == '/')
    rest.pop_back();
  const std::size_t colon = rest.rfind(':');
  if (colon == std::string::npos || colon == 0 || rest.find('/') != std::string::npos)
    return std::nullopt;
  HubAddress a;
  a.tls = tls;
  a.host = rest.substr(0, colon);
  const std::string port = rest.substr(colon + 1);
  if (port.empty() || port.size() > 5 ||
      !std::all_of(port.begin(), port.end(), [](char ch) { return ch >= '0' && ch <= '9'; }))
    return std::nullopt;
  const int p = std::stoi(port);
  if (p < 1 || p > 65535)
    return std::nullopt;
  if (!std::all_of(a.host.begin(), a.host.end(), [](char ch) {
        return std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '-';
      }))
    return std::nullopt;
  a.port = static_cast<std::uint16_t>(p);
  return a;
}

Config loadConfig(const std::filesystem::path& file, Config config) {
  std::ostringstream text;
  {
    std::ifstream in(file, std::ios::binary);
    if (!in)
      throw ConfigError(file.string() + ": cannot be read");
    text << in.rdbuf();
    if (in.bad())
      throw ConfigError(file.string() + ": read error");
  }
  return parseConfigText(text.str(), file.string(), std::move(config));
}

Config parseConfigText(const std::string& text, const std::string& fileName, Config config) {
  toml::value root;
  try {
    root = parseTomlText(text, fileName);
  } catch (const ConfigError&) {
    throw;
  } catch (const std::exception& e) {
    throw ConfigError(fileName + ": " + e.what());
  }
  if (!root.is_table())
    throw ConfigError(fileName + ": not a TOML table");
  const auto& tables = schema();
  for (const auto& [section, value] : root.as_table()) {
    auto t = tables.find(section);
    if (t == tables.end())
      throw ConfigError(fileName + ": [" + section + "]: unknown section");
    if (!value.is_table())
      throw ConfigError(fileName + ": " + section + ": must be a table [" + section + "]");
    for (const auto& [key, v] : value.as_table()) {
      const std::string name = "[" + section + "] " + key;
      auto setter = t->second.find(key);
      if (setter == t->second.end())
        throw ConfigError(fileName + ": " + name + ": unknown key");
      try {
        setter->second(v, config, name);
      } catch (const ConfigError& e) {
        throw ConfigError(fileName + ": " + e.what());
      }
    }
  }
  return config;
}

namespace {

// A JSON setting as the TOML value the [shop] setters check (strings, booleans, a table of
// strings); anything else is refused by those setters' own type checks.
toml::value tomlOf(const nlohmann::json& j) {
  if (j.is_string())
    return toml::value(j.get<std::string>());
  if (j.is_boolean())
    return toml::value(j.get<bool>());
  if (j.is_number_integer())
    return toml::value(j.get<std::int64_t>());
  if (j.is_number())
    return toml::value(j.get<double>());
  if (j.is_object()) {
    toml::table t;
    for (const auto& [k, v] : j.items())
      t[k] = tomlOf(v);
    return toml::value(t);
  }
  return toml::value(toml::array{});  // null or an array: no [shop] key takes one
}

}  // namespace

void applyShopSettings(const nlohmann::json& settings, ShopConfig& shop) {
  if (!settings.is_object())
    throw ConfigError("shop settings: must be a JSON object");
  const auto& setters = schema().at("shop");
  Config scratch;
  scratch.shop = shop;
  for (const auto& [key, v] : settings.items()) {
    const auto setter = setters.find(key);
    if (setter == setters.end())
      throw ConfigError("shop." + quoteInput(key) + ": unknown setting");
    setter->second(tomlOf(v), scratch, "shop." + key);
  }
  shop = scratch.shop;
}

nlohmann::json shopSettingsJson(const ShopConfig& shop) {
  return {{"brand", shop.brand},
          {"store_url", shop.storeUrl},
          {"public_base_url", shop.publicBaseUrl},
          {"store_platform", shop.storePlatform},
          {"currency", shop.currency},
          {"size_system", shop.sizeSystem},
          {"size_labels", shop.sizeLabels},
          {"made_to_order", shop.madeToOrder},
          {"allow_loopback", shop.allowLoopback}};
}

void applySimulated(Config& c) {
  c.cameraBackend = "synthetic";
  c.gpioBackend = "simulated";
#ifdef GARMCAP_DEFAULT_FORM
  if (c.formPath.empty())
    c.formPath = GARMCAP_DEFAULT_FORM;
#endif
}

}  // namespace garmcap::daemon
