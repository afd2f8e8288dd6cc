#include "garmcap/daemon/config.h"

#include <gtest/gtest.h>

#include <fstream>

#include "garmcap/daemon/http_server.h"
#include "garmcap/sim/synthetic_camera.h"
#include "test_util.h"

namespace garmcap::daemon {
namespace {

std::filesystem::path write(const test::TempDir& dir, const std::string& text) {
  auto p = dir.path() / "garmcapd.toml";
  std::ofstream(p) << text;
  return p;
}

std::string errorOf(const test::TempDir& dir, const std::string& text) {
  try {
    loadConfig(write(dir, text)).validate();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(Config, ReadsEveryTable) {
  test::TempDir dir;
  const Config c = loadConfig(write(dir, R"(
[camera]
backend = "replay"
device = "/srv/rig"
[gpio]
backend = "simulated"
debounce_ms = 40
[paths]
data = "/tmp/x"
[http]
listen = "0.0.0.0:9000"
token = "0123456789abcdef0123"
[pipeline]
review_below_confidence = 0.5
[naming]
template = "{id}-{kind}"
)"));
  EXPECT_EQ(c.cameraBackend, "replay");
  EXPECT_EQ(c.debounceMs, 40);
  EXPECT_EQ(c.listenAddress, "0.0.0.0");
  EXPECT_EQ(c.listenPort, 9000);
  EXPECT_DOUBLE_EQ(c.reviewBelowConfidence, 0.5);
  EXPECT_NO_THROW(c.validate());
}

// config.cpp spells the backend names out (it is in garmcap::http, without the camera or the
// simulator): they must stay the names the camera factory knows.
TEST(Config, AcceptsEveryCameraBackendTheFactoryKnows) {
  test::TempDir dir;
  for (const auto& b : sim::cameraBackends())
    EXPECT_EQ(loadConfig(write(dir, "[camera]\nbackend = \"" + b + "\"\n")).cameraBackend, b);
}

TEST(Config, RefusesWithKeyAndReason) {
  test::TempDir dir;
  EXPECT_NE(errorOf(dir, "[camera]\nbackend = \"webcam\"\n").find("[camera] backend"),
            std::string::npos);
  EXPECT_NE(errorOf(dir, "[http]\nlisten = \"127.0.0.1:70000\"\n").find("port"), std::string::npos);
  EXPECT_NE(errorOf(dir, "[http]\ncolour = 1\n").find("[http] colour: unknown key"),
            std::string::npos);
  EXPECT_NE(errorOf(dir, "[cameras]\n").find("unknown section"), std::string::npos);
  EXPECT_NE(errorOf(dir, "[pipeline]\nsize_chart = \"korean\"\n")
                .find("[pipeline] size_chart: unknown size chart 'korean' (known charts: "),
            std::string::npos);
  EXPECT_EQ(loadConfig(write(dir, "[pipeline]\nsize_chart = \"french_women\"\n")).sizeChart,
            "french_women");
  // The drop shadow on the product photos: off unless asked for, and only as a boolean.
  EXPECT_FALSE(loadConfig(write(dir, "[pipeline]\n")).productShadow);
  EXPECT_TRUE(loadConfig(write(dir, "[pipeline]\nproduct_shadow = true\n")).productShadow);
  EXPECT_NE(errorOf(dir, "[pipeline]\nproduct_shadow = \"yes\"\n")
                .find("[pipeline] product_shadow: must be true or false"),
            std::string::npos);
  // The marker piece limit: 60 unless set, 1 to 1000.
  EXPECT_EQ(loadConfig(write(dir, "[marker]\n")).markerMaxPieces, 60);
  EXPECT_EQ(loadConfig(write(dir, "[marker]\nmax_pieces = 120\n")).markerMaxPieces, 120);
  EXPECT_NE(errorOf(dir, "[marker]\nmax_pieces = 0\n").find("[marker] max_pieces"),
            std::string::npos);
  EXPECT_NE(errorOf(dir, "[gpio]\ndebounce_ms = \"x\"\n").find("must be an integer"),
            std::string::npos);
  EXPECT_NE(errorOf(dir, "[http]\nlisten = \"0.0.0.0:8080\"\n").find("token"), std::string::npos);
  EXPECT_NE(errorOf(dir, "[http\n").find("garmcapd.toml"), std::string::npos);
  // Not UTF-8: refused before toml11 sees it (its literal-string parser reads out of bounds on
  // such bytes; tests/fuzz/fuzz_config_toml found it).
  EXPECT_NE(errorOf(dir,
                    "' \xaf"
                    "etc' = 1\n")
                .find("not valid UTF-8"),
            std::string::npos);
  EXPECT_NE(errorOf(dir, "[http]\nserver_names = [\"a b\"]\n").find("server_names"),
            std::string::npos);
}

// Text already read (the fuzzer's way in) is checked as a file's is, and named as given; a file
// that cannot be read is named too.
TEST(Config, TextAndFileReadTheSameWay) {
  test::TempDir dir;
  const std::string text = "[gpio]\ndebounce_ms = 25\n";
  EXPECT_EQ(parseConfigText(text, "inline.toml").debounceMs,
            loadConfig(write(dir, text)).debounceMs);
  try {
    parseConfigText("[gpio]\ndebounce_ms = \"x\"\n", "inline.toml");
    ADD_FAILURE() << "a string debounce was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("inline.toml: [gpio] debounce_ms", 0), 0u) << e.what();
  }
  try {
    loadConfig(dir.path() / "missing.toml");
    ADD_FAILURE() << "a missing file was read";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.toml: cannot be read"), std::string::npos)
        << e.what();
  }
}

TEST(Config, ListenParsingAndLoopback) {
  Config c;
  parseListen("[::1]:8081", c, "--listen");
  EXPECT_EQ(c.listenAddress, "::1");
  EXPECT_TRUE(c.loopbackOnly());
  parseListen("127.0.0.2:1", c, "--listen");
  EXPECT_TRUE(c.loopbackOnly());
  parseListen("192.168.1.5:80", c, "--listen");
  EXPECT_FALSE(c.loopbackOnly());
  EXPECT_THROW(parseListen("localhost:80", c, "--listen"), ConfigError);
  EXPECT_THROW(parseListen("8080", c, "--listen"), ConfigError);
}

TEST(Auth, BearerHeaderOrQueryToken) {
  Request r{http::verb::get, "/api/status", 11};
  EXPECT_TRUE(authorized(r, ""));
  EXPECT_FALSE(authorized(r, "secret-token-1234"));
  r.set(http::field::authorization, "Bearer secret-token-1234");
  EXPECT_TRUE(authorized(r, "secret-token-1234"));
  r.set(http::field::authorization, "Bearer secret-token-123");
  EXPECT_FALSE(authorized(r, "secret-token-1234"));
  Request q{http::verb::get, "/api/events?x=1&token=secret-token-1234", 11};
  EXPECT_TRUE(authorized(q, "secret-token-1234"));
  Request post{http::verb::post, "/api/button?token=secret-token-1234", 11};
  EXPECT_FALSE(authorized(post, "secret-token-1234"));  // query tokens only for GET streams
  EXPECT_TRUE(needsToken("/api/items"));
  EXPECT_TRUE(needsToken("/stream.mjpg"));
  EXPECT_FALSE(needsToken("/index.html"));
}

TEST(ShopSettings, SetupScreenValuesGetTheConfigFilesChecksAndRoundTrip) {
  ShopConfig shop;
  shop.brand = "From the config";
  applyShopSettings({{"brand", "Atelier"},
                     {"store_url", "https://atelier.example"},
                     {"size_labels", {{"55", "S"}}},
                     {"made_to_order", true}},
                    shop);
  EXPECT_EQ(shop.brand, "Atelier");
  EXPECT_EQ(shop.sizeLabels.at("55"), "S");
  EXPECT_TRUE(shop.madeToOrder);
  EXPECT_EQ(shop.currency, "EUR");  // untouched keys keep their value
  ShopConfig back;
  applyShopSettings(shopSettingsJson(shop), back);
  EXPECT_EQ(shopSettingsJson(back), shopSettingsJson(shop));
  const ShopConfig before = shop;
  for (const auto& [bad, key] : std::vector<std::pair<nlohmann::json, std::string>>{
           {{{"currency", "euro"}}, "shop.currency"},
           {{{"store_url", "javascript:alert(1)"}}, "shop.store_url"},
           {{{"store_platform", "etsy"}}, "shop.store_platform"},
           {{{"size_system", "XX"}}, "shop.size_system"},
           {{{"brand", std::string("a\nb")}}, "shop.brand"},
           {{{"allow_loopback", 1}}, "shop.allow_loopback"},
           {{{"brand", "ok"}, {"banner", "x"}}, "banner"},
           {nlohmann::json::array(), "JSON object"}}) {
    try {
      applyShopSettings(bad, shop);
      ADD_FAILURE() << bad.dump() << " was accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
    EXPECT_EQ(shopSettingsJson(shop), shopSettingsJson(before)) << bad.dump() << " changed it";
  }
}

}  // namespace
}  // namespace garmcap::daemon
