#include "garmcap/hub/hub_config.h"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <toml.hpp>

#include "garmcap/daemon/config.h"
#include "garmcap/daemon/content_store.h"
#include "garmcap/daemon/toml_input.h"
#include "garmcap/daemon/utf8.h"

namespace garmcap::hub {

namespace {

[[noreturn]] void bad(const std::string& where, const std::string& reason) {
  throw HubConfigError(where + ": " + reason);
}

std::string hashValue(const toml::value& v, const std::string& key) {
  if (!v.is_string() || !daemon::isSha256Hex(v.as_string().str))
    bad(key, "must be 64 lower-case hex digits (garmcap-hub hash-token TOKEN prints them)");
  return v.as_string().str;
}

// The [shop] table as the JSON that daemon::applyShopSettings reads (the station's settings
// form): strings, booleans and tables of strings; another type is passed on for its checks to
// refuse by name.
nlohmann::json shopJson(const toml::value& v) {
  if (v.is_string())
    return v.as_string().str;
  if (v.is_boolean())
    return v.as_boolean();
  if (v.is_integer())
    return v.as_integer();
  if (v.is_floating())
    return v.as_floating();
  if (v.is_table()) {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [k, x] : v.as_table())
      out[k] = shopJson(x);
    return out;
  }
  return nullptr;
}

}  // namespace

std::string defaultHubWebDir() {
  return GARMCAP_HUB_WEB_DIR;
}

bool validStationId(const std::string& id) {
  return !id.empty() && id.size() <= 64 && std::all_of(id.begin(), id.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_';
  });
}

std::string tokenHash(const std::string& token) {
  return daemon::sha256Hex(token);
}

void addStation(HubConfig& config, const std::string& spec, const std::string& what) {
  const std::size_t eq = spec.find('=');
  if (eq == std::string::npos)
    bad(what, "expected NAME=TOKEN_SHA256, got '" + daemon::quoteInput(spec) + "'");
  const std::string name = spec.substr(0, eq), hash = spec.substr(eq + 1);
  if (!validStationId(name))
    bad(what,
        "station name must be 1..64 of [A-Za-z0-9_-], got '" + daemon::quoteInput(name) + "'");
  if (!daemon::isSha256Hex(hash))
    bad(what, "the token hash of '" + name + "' must be 64 lower-case hex digits");
  config.stationTokenSha256[name] = hash;
}

void HubConfig::validate() const {
  if (databaseUrl.empty())
    throw HubConfigError("[database] url: required (a libpq connection string)");
  if (tls()) {
    if (tlsCertFile.empty())
      throw HubConfigError("[tls] cert_file: required with [tls] key_file (--tls-cert)");
    if (tlsKeyFile.empty())
      throw HubConfigError("[tls] key_file: required with [tls] cert_file (--tls-key)");
    using Entry = std::pair<std::string, std::string>;
    for (const auto& [key, file] : {Entry{"cert_file", tlsCertFile}, Entry{"key_file", tlsKeyFile}})
      if (!std::ifstream(file, std::ios::binary))
        throw HubConfigError(
            "[tls] " + key + ": " + file + ": " +
            (std::filesystem::exists(file) ? "cannot be read (permissions?)" : "no such file"));
  }
  daemon::Config probe;
  probe.listenAddress = listenAddress;
  if (!probe.loopbackOnly() && !tls())
    throw HubConfigError("[http] listen: " + listenAddress +
                         " is not a loopback address: set [tls] cert_file and key_file "
                         "(--tls-cert, --tls-key) to serve HTTPS there (docs/hub.md, \"TLS\")");
  std::map<std::string, std::string> seen;
  for (const auto& [station, hash] : stationTokenSha256) {
    if (hash == adminTokenSha256)
      throw HubConfigError("[stations] " + station + ": same token as the admin token");
    if (auto [it, fresh] = seen.emplace(hash, station); !fresh)
      throw HubConfigError("[stations] " + station + ": same token as station " + it->second);
  }
}

HubConfig loadHubConfig(const std::filesystem::path& file, HubConfig c) {
  const std::string f = file.string();
  toml::value root;
  try {
    std::ifstream in(file, std::ios::binary);
    if (!in)
      throw HubConfigError(f + ": cannot be read");
    std::ostringstream text;
    text << in.rdbuf();
    root = daemon::parseTomlText(text.str(), f);
  } catch (const HubConfigError&) {
    throw;
  } catch (const std::exception& e) {
    throw HubConfigError(f + ": " + e.what());
  }
  if (!root.is_table())
    throw HubConfigError(f + ": not a TOML table");
  for (const auto& [section, table] : root.as_table()) {
    if (!table.is_table())
      bad(f + ": " + section, "must be a table [" + section + "]");
    if (section == "shop") {
      // The station's [shop] keys, through the station's own checks.
      try {
        daemon::applyShopSettings(shopJson(table), c.shop);
      } catch (const daemon::ConfigError& e) {
        bad(f + ": [shop]", e.what());
      }
      continue;
    }
    // Key and value by name, not by structured binding: clang 14 (the sanitized build,
    // tests/fuzz) cannot capture a binding in a lambda.
    for (const auto& entry : table.as_table()) {
      const std::string& key = entry.first;
      const auto& v = entry.second;
      const std::string name = f + ": [" + section + "] " + key;
      auto integer = [&](long long lo, long long hi) {
        if (!v.is_integer() || v.as_integer() < lo || v.as_integer() > hi)
          bad(name, "must be an integer " + std::to_string(lo) + ".." + std::to_string(hi));
        return v.as_integer();
      };
      if (section == "database" && key == "url") {
        if (!v.is_string())
          bad(name, "must be a string");
        c.databaseUrl = v.as_string().str;
      } else if (section == "database" && key == "connections") {
        c.connections = static_cast<int>(integer(1, 64));
      } else if (section == "http" && key == "listen") {
        if (!v.is_string())
          bad(name, "must be a string \"HOST:PORT\"");
        daemon::Config probe;
        try {
          daemon::parseListen(v.as_string().str, probe, name);
        } catch (const daemon::ConfigError& e) {
          throw HubConfigError(e.what());
        }
        c.listenAddress = probe.listenAddress;
        c.listenPort = probe.listenPort;
      } else if (section == "http" && key == "admin_token_sha256") {
        c.adminTokenSha256 = hashValue(v, name);
      } else if (section == "http" && key == "body_limit_bytes") {
        c.bodyLimitBytes = static_cast<std::size_t>(integer(1024, 1LL << 30));
      } else if (section == "http" && key == "web_dir") {
        if (!v.is_string() || v.as_string().str.empty())
          bad(name, "must be the path of a folder");
        c.webDir = v.as_string().str;
      } else if (section == "http" && key == "request_timeout_s") {
        c.requestTimeoutS = static_cast<int>(integer(1, 3600));
      } else if (section == "http" && key == "min_send_rate") {
        c.minSendRate = static_cast<std::size_t>(integer(1024, 1LL << 30));
      } else if (section == "http" && key == "threads") {
        c.threads = static_cast<int>(integer(1, 64));
      } else if (section == "tls" && (key == "cert_file" || key == "key_file")) {
        if (!v.is_string() || v.as_string().str.empty())
          bad(name, "must be the path of a PEM file");
        (key == "cert_file" ? c.tlsCertFile : c.tlsKeyFile) = v.as_string().str;
      } else if (section == "stations") {
        if (!validStationId(key))
          bad(name, "a station name is 1..64 of [A-Za-z0-9_-]");
        c.stationTokenSha256[key] = hashValue(v, name);
      } else if (section != "database" && section != "http" && section != "stations" &&
                 section != "tls") {
        bad(f + ": [" + section + "]", "unknown section");
      } else {
        bad(name, "unknown key");
      }
    }
  }
  return c;
}

}  // namespace garmcap::hub
