#pragma once
// garmcap-hub configuration: a TOML file, then command-line flags on top (docs/hub.md).
//
//   [database]
//   url = "host=/run/postgresql dbname=garmcap_hub"   # a libpq connection string
//   connections = 4
//   [http]
//   listen = "127.0.0.1:8090"        # any address with [tls]; loopback only without
//   admin_token_sha256 = "<64 hex>"   # reads and edits at the hub (garmcap-hub hash-token T)
//   body_limit_bytes = 67108864       # the largest blob a station may send
//   web_dir = "/usr/share/garmcap/hub-web"   # the review UI's files (default: the build's)
//   request_timeout_s = 30            # a request's body; a download's piece: this plus
//   min_send_rate = 32768             # its size at this many bytes/s, or the client is cut
//   [tls]                             # HTTPS (docs/hub.md, "TLS")
//   cert_file = "/etc/garmcap-hub/tls/cert.pem"   # the certificate, then intermediates
//   key_file = "/etc/garmcap-hub/tls/key.pem"     # its private key, unencrypted
//   [stations]
//   shop1 = "<64 hex: sha256 of shop1's token>"
//   [shop]                            # the chain's shop exports: the station's [shop] keys
//   brand = "..."                     # (docs/daemon.md), checked by the station's rules
//
// Only hashes of tokens are stored: a leaked config file does not let anyone push. Strict like
// the station's: an unknown key, a wrong type or a bad value throws HubConfigError naming the
// file and the key.

#include <cstdint>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>

#include "garmcap/daemon/config.h"

namespace garmcap::hub {

class HubConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Where the build put the hub's web UI (daemon/hub/CMakeLists.txt), unless --web-dir or
/// [http] web_dir say otherwise.
std::string defaultHubWebDir();

struct HubConfig {
  std::string databaseUrl;
  int connections = 4;
  std::string listenAddress = "127.0.0.1";
  std::uint16_t listenPort = 8090;
  std::string adminTokenSha256;                           // "" = no admin access over HTTP
  std::map<std::string, std::string> stationTokenSha256;  // station id -> token hash
  std::size_t bodyLimitBytes = 64u << 20;
  int threads = 4;
  // A response, or each piece of an export, must reach the client within requestTimeoutS plus
  // its size at minSendRate bytes per second (daemon::writeDeadline), or the connection is
  // closed: a client that stops reading gives its export slot back.
  int requestTimeoutS = 30;
  std::size_t minSendRate = 32 * 1024;
  std::string webDir = defaultHubWebDir();  // the review UI's static files, served at "/"
  std::string tlsCertFile;  // both set: HTTPS; both empty: plain HTTP (loopback only)
  std::string tlsKeyFile;
  daemon::ShopConfig shop;  // [shop]: defaults of the chain's shop exports

  bool tls() const { return !tlsCertFile.empty() || !tlsKeyFile.empty(); }
  /// Throws HubConfigError when incomplete (no database, half a [tls] section, a TLS file that
  /// cannot be read) or unsafe (a non-loopback address without TLS). Whether the key matches the
  /// certificate is checked when the server starts (daemon::makeServerTlsContext).
  void validate() const;
};

/// Reads a TOML file over the defaults.
HubConfig loadHubConfig(const std::filesystem::path& file, HubConfig defaults = {});
/// "NAME=HASH" of --station; throws HubConfigError naming the flag.
void addStation(HubConfig& config, const std::string& spec, const std::string& what);
/// The hash the hub keeps of a token (lower-case hex sha256).
std::string tokenHash(const std::string& token);
bool validStationId(const std::string& id);

}  // namespace garmcap::hub
