// garmcap-hub: several stations, one catalog on PostgreSQL (docs/hub.md).
//
//   garmcap-hub --config /etc/garmcap/hub.toml
//   garmcap-hub --db "host=/run/postgresql dbname=garmcap_hub" --listen 127.0.0.1:8090
//               --station shop1=<sha256 of its token> --admin-token-sha256 <sha256>
//   garmcap-hub --config ... --listen 0.0.0.0:8443 --tls-cert cert.pem --tls-key key.pem
//   garmcap-hub hash-token TOKEN      prints the hash to put in the config
#include <signal.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <iostream>

#include "garmcap/daemon/config.h"
#include "garmcap/hub/hub_config.h"
#include "garmcap/hub/hub_service.h"

int main(int argc, char** argv) {
  using namespace garmcap;
  CLI::App app{"garmcap-hub: the chain's catalog for several GarmCap stations"};
  std::string configFile, db, listen, adminHash, logLevel = "info", token, tlsCert, tlsKey, webDir;
  std::vector<std::string> stations;
  app.add_option("-c,--config", configFile, "TOML configuration file")->check(CLI::ExistingFile);
  app.add_option("--db", db, "libpq connection string (overrides [database] url)");
  app.add_option("--listen", listen,
                 "address HOST:PORT (default 127.0.0.1:8090; not loopback only with TLS)");
  app.add_option("--tls-cert", tlsCert, "PEM certificate chain: serve HTTPS ([tls] cert_file)");
  app.add_option("--tls-key", tlsKey, "PEM private key of --tls-cert ([tls] key_file)");
  app.add_option("--station", stations, "NAME=TOKEN_SHA256 of a station (repeatable)");
  app.add_option("--admin-token-sha256", adminHash, "sha256 of the admin token");
  app.add_option("--web-dir", webDir, "the review UI's files ([http] web_dir)");
  app.add_option("--log-level", logLevel, "trace, debug, info, warn, error");
  auto* hash = app.add_subcommand("hash-token", "print the hash of a token for the config");
  hash->add_option("token", token, "the token")->required();
  CLI11_PARSE(app, argc, argv);
  if (hash->parsed()) {
    std::cout << hub::tokenHash(token) << "\n";
    return 0;
  }
  // Logs go to stderr (the journal under systemd); stdout carries only the "listening" line.
  spdlog::set_default_logger(spdlog::stderr_color_mt("garmcap-hub"));
  spdlog::set_level(spdlog::level::from_str(logLevel));

  hub::HubConfig config;
  try {
    if (!configFile.empty())
      config = hub::loadHubConfig(configFile);
    if (!db.empty())
      config.databaseUrl = db;
    if (!listen.empty()) {
      daemon::Config probe;
      daemon::parseListen(listen, probe, "--listen");
      config.listenAddress = probe.listenAddress;
      config.listenPort = probe.listenPort;
    }
    if (!adminHash.empty()) {
      config.adminTokenSha256 = adminHash;
      if (adminHash.size() != 64)
        throw hub::HubConfigError("--admin-token-sha256: must be 64 lower-case hex digits");
    }
    if (!tlsCert.empty())
      config.tlsCertFile = tlsCert;
    if (!tlsKey.empty())
      config.tlsKeyFile = tlsKey;
    if (!webDir.empty())
      config.webDir = webDir;
    for (const auto& s : stations)
      hub::addStation(config, s, "--station");
    config.validate();
  } catch (const std::exception& e) {
    std::cerr << "garmcap-hub: invalid configuration: " << e.what() << "\n";
    return 2;
  }

  // SIGTERM and SIGINT are waited for below, not handled asynchronously.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  std::unique_ptr<hub::HubService> service;
  try {
    service = std::make_unique<hub::HubService>(config);
    service->start();
  } catch (const std::exception& e) {
    std::cerr << "garmcap-hub: cannot start: " << e.what() << "\n";
    return 1;
  }
  spdlog::info("garmcap-hub: {} station(s), schema {}", config.stationTokenSha256.size(),
               service->store().schemaVersion());
  spdlog::info("garmcap-hub: {}", config.tls() ? "HTTPS (TLS 1.2 and later)" : "plain HTTP");
  std::cout << "garmcap-hub listening on " << config.listenAddress << ":" << service->port()
            << std::endl;
  int sig = 0;
  sigwait(&signals, &sig);
  spdlog::info("garmcap-hub: signal {}, stopping", sig);
  service->stop();
  return 0;
}
