// The hub's configuration without a database: hub.toml read strictly ([database], [http],
// [stations], [shop], [tls], the write deadline), the checks of validate() and the TLS
// certificate and key checks at start (certificates made at test time, common/test_certs.h). No
// PostgreSQL, so these also run under ASan+UBSan in CI (tests/fuzz/CMakeLists.txt,
// sanitized_daemon_tests).
#include "garmcap/hub/hub_config.h"

#include <gtest/gtest.h>
#include <openssl/ssl.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "../common/temp_folder.h"
#include "../common/test_certs.h"
#include "garmcap/daemon/tls_context.h"

namespace garmcap::hub {
namespace {

namespace fs = std::filesystem;

HubConfig minimalConfig() {
  HubConfig c;
  c.databaseUrl = "dbname=x";
  return c;
}

std::string messageOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(HubTlsConfig, ANonLoopbackAddressNeedsTls) {
  garmcap::testing::TempFolder dir{"garmcap-hubtlscfg"};
  const garmcap::test::TestCerts certs(dir.path());
  HubConfig c = minimalConfig();
  c.listenAddress = "0.0.0.0";
  const std::string why = messageOf([&] { c.validate(); });
  EXPECT_NE(why.find("[http] listen: 0.0.0.0 is not a loopback address"), std::string::npos) << why;
  EXPECT_NE(why.find("[tls] cert_file"), std::string::npos) << why;
  c.tlsCertFile = certs.serverCert.string();
  c.tlsKeyFile = certs.serverKey.string();
  EXPECT_NO_THROW(c.validate());
  c.listenAddress = "::";
  EXPECT_NO_THROW(c.validate());
  // Loopback may stay plain HTTP.
  EXPECT_NO_THROW(minimalConfig().validate());
}

TEST(HubTlsConfig, TheTlsSectionIsReadAndItsFilesAreNamedWhenMissing) {
  garmcap::testing::TempFolder dir{"garmcap-hubtlscfg"};
  const garmcap::test::TestCerts certs(dir.path());
  const auto file = dir.path() / "hub.toml";
  std::ofstream(file) << "[database]\nurl = \"dbname=x\"\n[http]\nlisten = \"0.0.0.0:8443\"\n"
                      << "[tls]\ncert_file = \"" << certs.serverCert.string() << "\"\n"
                      << "key_file = \"" << (dir.path() / "nokey.pem").string() << "\"\n";
  HubConfig c = loadHubConfig(file);
  EXPECT_EQ(c.tlsCertFile, certs.serverCert.string());
  EXPECT_TRUE(c.tls());
  std::string why = messageOf([&] { c.validate(); });
  EXPECT_NE(why.find("[tls] key_file: " + (dir.path() / "nokey.pem").string() + ": no such file"),
            std::string::npos)
      << why;
  c.tlsKeyFile.clear();
  why = messageOf([&] { c.validate(); });
  EXPECT_NE(why.find("[tls] key_file: required with [tls] cert_file"), std::string::npos) << why;
  std::ofstream(file) << "[tls]\ncert = \"x\"\n";
  why = messageOf([&] { loadHubConfig(file); });
  EXPECT_NE(why.find("[tls] cert: unknown key"), std::string::npos) << why;
  std::ofstream(file) << "[tls]\nkey_file = 3\n";
  EXPECT_THROW(loadHubConfig(file), HubConfigError);
}

TEST(HubTlsConfig, AKeyThatDoesNotMatchTheCertificateIsNamedAtStart) {
  garmcap::testing::TempFolder dir{"garmcap-hubtlscfg"};
  const garmcap::test::TestCerts certs(dir.path());
  const auto ctx = daemon::makeServerTlsContext(certs.serverCert, certs.serverKey);
  EXPECT_EQ(SSL_CTX_get_min_proto_version(ctx->native_handle()), TLS1_2_VERSION);
  std::string why = messageOf([&] { daemon::makeServerTlsContext(certs.serverCert, certs.caKey); });
  EXPECT_NE(why.find("TLS key " + certs.caKey.string() + ": does not match the certificate in " +
                     certs.serverCert.string()),
            std::string::npos)
      << why;
  // The two swapped: the "certificate" is a key.
  why = messageOf([&] { daemon::makeServerTlsContext(certs.serverKey, certs.serverCert); });
  EXPECT_NE(why.find("TLS certificate " + certs.serverKey.string() + ": not a PEM certificate"),
            std::string::npos)
      << why;
  why = messageOf(
      [&] { daemon::makeServerTlsContext(dir.path() / "none.pem", certs.serverKey.string()); });
  EXPECT_NE(why.find((dir.path() / "none.pem").string() + ": cannot be read"), std::string::npos)
      << why;
}

TEST(HubConfig, ReadsTomlStrictlyAndRefusesUnsafeListen) {
  namespace fs = std::filesystem;
  const auto dir = fs::temp_directory_path() / ("garmcap-hubcfg-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const auto file = dir / "hub.toml";
  const std::string h1 = tokenHash("a"), h2 = tokenHash("b");
  std::ofstream(file) << "[database]\nurl = \"dbname=x\"\n[http]\nlisten = \"127.0.0.1:9000\"\n"
                      << "admin_token_sha256 = \"" << tokenHash("admin") << "\"\n"
                      << "[stations]\nshop1 = \"" << h1 << "\"\nshop2 = \"" << h2 << "\"\n";
  HubConfig c = loadHubConfig(file);
  EXPECT_EQ(c.databaseUrl, "dbname=x");
  EXPECT_EQ(c.listenPort, 9000);
  EXPECT_EQ(c.stationTokenSha256.at("shop2"), h2);
  EXPECT_NO_THROW(c.validate());
  c.listenAddress = "0.0.0.0";
  EXPECT_THROW(c.validate(), HubConfigError);  // without [tls]: loopback only
  std::ofstream(file) << "[stations]\nshop1 = \"not-a-hash\"\n";
  try {
    loadHubConfig(file);
    FAIL();
  } catch (const HubConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("[stations] shop1"), std::string::npos) << e.what();
  }
  std::ofstream(file) << "[http]\nport = 1\n";
  EXPECT_THROW(loadHubConfig(file), HubConfigError);
  // Read through the station's TOML checks: toml11 3.7.1 overflowed its stack on this (SIGSEGV).
  std::ofstream(file) << "[stations]\nx = " << std::string(100000, '[') << "\n";
  try {
    loadHubConfig(file);
    FAIL();
  } catch (const HubConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("line 2: arrays, inline tables or table headers nested"),
              std::string::npos)
        << e.what();
  }
  HubConfig dup;
  dup.databaseUrl = "x";
  addStation(dup, "a=" + h1, "--station");
  addStation(dup, "b=" + h1, "--station");
  EXPECT_THROW(dup.validate(), HubConfigError);
  EXPECT_THROW(addStation(dup, "a b=" + h1, "--station"), HubConfigError);
  fs::remove_all(dir);
}

// [shop]: the station's keys, by the station's checks, named with the file when refused.
TEST(HubConfig, ShopSectionTakesTheStationsKeysAndChecks) {
  namespace fs = std::filesystem;
  const auto dir = fs::temp_directory_path() / ("garmcap-hubshop-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const auto file = dir / "hub.toml";
  std::ofstream(file) << "[shop]\nbrand = \"Chain\"\nstore_url = \"https://shop.test\"\n"
                      << "made_to_order = true\n[shop.size_labels]\n\"55\" = \"S\"\n";
  const HubConfig c = loadHubConfig(file);
  EXPECT_EQ(c.shop.brand, "Chain");
  EXPECT_EQ(c.shop.storeUrl, "https://shop.test");
  EXPECT_TRUE(c.shop.madeToOrder);
  EXPECT_EQ(c.shop.sizeLabels.at("55"), "S");
  for (const std::string bad : {"[shop]\nstore_url = \"ftp://x\"\n", "[shop]\nbrandd = \"x\"\n",
                                "[shop]\nmade_to_order = \"yes\"\n"}) {
    std::ofstream(file) << bad;
    try {
      loadHubConfig(file);
      ADD_FAILURE() << bad;
    } catch (const HubConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("[shop]"), std::string::npos) << e.what();
    }
  }
  fs::remove_all(dir);
}

// The write deadline of responses and downloads: request_timeout_s plus the size at
// min_send_rate bytes per second (daemon::writeDeadline), both configurable and checked.
TEST(HubConfig, WriteDeadlineKeys) {
  namespace fs = std::filesystem;
  const auto dir = fs::temp_directory_path() / ("garmcap-hubrate-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const auto file = dir / "hub.toml";
  EXPECT_EQ(HubConfig{}.requestTimeoutS, 30);
  EXPECT_EQ(HubConfig{}.minSendRate, 32u * 1024);
  std::ofstream(file) << "[http]\nrequest_timeout_s = 5\nmin_send_rate = 65536\n";
  const HubConfig c = loadHubConfig(file);
  EXPECT_EQ(c.requestTimeoutS, 5);
  EXPECT_EQ(c.minSendRate, 65536u);
  for (const std::string bad : {"[http]\nmin_send_rate = 100\n", "[http]\nrequest_timeout_s = 0\n",
                                "[http]\nmin_send_rate = \"fast\"\n"}) {
    std::ofstream(file) << bad;
    EXPECT_THROW(loadHubConfig(file), HubConfigError) << bad;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace garmcap::hub
