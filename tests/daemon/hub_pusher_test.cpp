// The pusher's retry schedule and the [hub] configuration (the pushing itself runs against the
// real hub in tests/hub/hub_e2e_test.cpp).
#include "garmcap/daemon/hub_pusher.h"

#include <gtest/gtest.h>

#include <fstream>

#include "garmcap/daemon/config.h"
#include "test_util.h"

namespace garmcap::daemon {
namespace {

using std::chrono::milliseconds;

TEST(HubPusher, BackoffDoublesFromHalfASecondToThirtySeconds) {
  EXPECT_EQ(hubBackoff(0), milliseconds(0));
  EXPECT_EQ(hubBackoff(1), milliseconds(500));
  EXPECT_EQ(hubBackoff(2), milliseconds(1000));
  EXPECT_EQ(hubBackoff(3), milliseconds(2000));
  EXPECT_EQ(hubBackoff(7), milliseconds(30000));  // 32 s capped
  EXPECT_EQ(hubBackoff(1000), milliseconds(30000));
}

TEST(HubConfig, UrlIsHttpHostPortAndNeedsAToken) {
  auto a = parseHubUrl("http://127.0.0.1:8090");
  ASSERT_TRUE(a);
  EXPECT_EQ(a->host, "127.0.0.1");
  EXPECT_EQ(a->port, 8090);
  EXPECT_TRUE(parseHubUrl("http://hub.local:80/"));
  for (const char* bad : {"https://127.0.0.1:8090", "http://127.0.0.1", "http://:80", "http://h:0",
                          "http://h:70000", "http://h:80/api", "ftp://h:1", "http://h h:80"})
    EXPECT_FALSE(parseHubUrl(bad)) << bad;
  test::TempDir dir;
  const auto file = dir.path() / "c.toml";
  std::ofstream(file) << "[hub]\nurl = \"http://127.0.0.1:8090\"\ntoken = \"t\"\npoll_ms = 100\n";
  Config c = loadConfig(file);
  EXPECT_EQ(c.hubUrl, "http://127.0.0.1:8090");
  EXPECT_EQ(c.hubToken, "t");
  EXPECT_EQ(c.hubPollMs, 100);
  EXPECT_NO_THROW(c.validate());
  c.hubToken.clear();
  EXPECT_THROW(c.validate(), ConfigError);
  std::ofstream(file) << "[hub]\nurl = \"https://hub:443\"\n";
  try {
    loadConfig(file);
    FAIL() << "https must be refused until TLS is in";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("[hub] url"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace garmcap::daemon
