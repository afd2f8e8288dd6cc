// The HTTP session that garmcapd runs per connection, driven over beast::test::stream (no socket):
// raw bytes in, raw bytes out, through the real router, API routes and static-file whitelist.
// Covers what a hostile or broken client can send: bad framing, oversize bodies and headers,
// missing or wrong tokens, path traversal, malformed JSON, unknown routes.
#include "garmcap/daemon/http_session.h"

#include <gtest/gtest.h>

#include <boost/beast/_experimental/test/stream.hpp>
#include <fstream>
#include <nlohmann/json.hpp>

#include "station_rig.h"

namespace garmcap::daemon {
namespace {

using namespace std::chrono_literals;
namespace beast = boost::beast;

constexpr const char* kToken = "unit-test-token-0123456789";

struct Parsed {
  std::vector<Response> responses;
  std::string rest;  // bytes after the last complete response (a stream body, or garbage)
};

Parsed parseResponses(std::string_view raw) {
  Parsed out;
  while (!raw.empty()) {
    http::response_parser<http::string_body> parser;
    parser.eager(true);
    beast::error_code ec;
    const std::size_t used = parser.put(boost::asio::buffer(raw.data(), raw.size()), ec);
    if (ec || !parser.is_done()) {
      out.rest = std::string(raw);
      break;
    }
    out.responses.push_back(parser.release());
    raw.remove_prefix(used);
  }
  return out;
}

// A server session on one end of a test stream; the test writes raw requests into it and reads
// what the session wrote to the other end.
class SessionRig {
 public:
  explicit SessionRig(std::string token = "", std::size_t bodyLimit = 4096) {
    std::filesystem::create_directories(web_ / "img");
    std::ofstream(web_ / "index.html") << "<html>station</html>";
    std::ofstream(web_ / "img" / "logo.svg") << "<svg/>";
    std::ofstream(rig.dir.path() / "secret.txt") << "outside the web folder";
    files_ = std::make_unique<StaticFiles>(web_.string());
    Config c;
    c.token = std::move(token);
    c.bodyLimitBytes = bodyLimit;
    c.serverNames = {"t"};  // the Host the raw requests below carry
    shared_.reset(new ServerShared{c, rig.router, *files_});
  }

  /// Sends `raw` (one or more requests), then end-of-stream, and runs the loop until the
  /// session ends. Returns the responses in order.
  Parsed exchange(const std::string& raw) {
    beast::test::stream server(rig.io), client(rig.io);
    client.connect(server);
    server.append(raw);
    server.close_remote();
    serveConnection(std::move(server), shared_);
    const bool ended = rig.runUntil([&] { return shared_->sessions.load() == 0; });
    EXPECT_TRUE(ended) << "the session did not end";
    const auto got = client.str();
    return parseResponses(std::string_view(got.data(), got.size()));
  }
  /// For streams: keeps the connection open until `text` arrived, then the client leaves.
  std::string streamUntil(const std::string& raw, const std::string& text) {
    beast::test::stream server(rig.io), client(rig.io);
    client.connect(server);
    server.append(raw);
    serveConnection(std::move(server), shared_);
    EXPECT_TRUE(rig.runUntil([&] { return client.str().find(text) != std::string::npos; }))
        << "no '" << text << "' in: " << std::string(client.str());
    client.close();
    EXPECT_TRUE(rig.runUntil([&] { return shared_->sessions.load() == 0; }))
        << "the stream session did not end when the client left";
    return std::string(client.str());
  }
  Response one(const std::string& raw) {
    auto p = exchange(raw);
    EXPECT_EQ(p.responses.size(), 1u) << client(raw) << "\n--- got:\n" << p.rest;
    return p.responses.empty() ? Response{} : p.responses.front();
  }
  static std::string client(const std::string& raw) { return raw.substr(0, 200); }

  test::Rig rig;

 private:
  std::filesystem::path web_ = rig.dir.path() / "web";
  std::unique_ptr<StaticFiles> files_;
  std::shared_ptr<ServerShared> shared_;
};

std::string get(const std::string& target, const std::string& extra = "") {
  return "GET " + target + " HTTP/1.1\r\nHost: t\r\n" + extra + "\r\n";
}
std::string withBody(const std::string& verb, const std::string& target, const std::string& body,
                     const std::string& extra = "") {
  return verb + " " + target + " HTTP/1.1\r\nHost: t\r\nContent-Type: application/json\r\n" +
         extra + "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
}
std::string errorOf(const Response& r) {
  auto j = nlohmann::json::parse(r.body(), nullptr, false);
  EXPECT_TRUE(j.is_object() && j.contains("error")) << "not a JSON error: " << r.body();
  return j.is_object() ? j.value("error", "") : "";
}
bool isJson(const Response& r) {
  return r[http::field::content_type] == "application/json";
}

TEST(HttpSession, KeepAliveServesSeveralRequestsInOrder) {
  SessionRig s;
  auto p = s.exchange(get("/api/status") + get("/api/items") + get("/"));
  ASSERT_EQ(p.responses.size(), 3u) << p.rest;
  EXPECT_EQ(nlohmann::json::parse(p.responses[0].body())["state"], "uncalibrated");
  EXPECT_EQ(nlohmann::json::parse(p.responses[1].body())["total"], 0);
  EXPECT_EQ(p.responses[2].body(), "<html>station</html>");
  EXPECT_EQ(p.responses[2]["X-Content-Type-Options"], "nosniff");
}

TEST(HttpSession, MalformedRequestsGet400AndTheConnectionCloses) {
  SessionRig s;
  for (const std::string& raw : {
           std::string("GARBAGE\r\n\r\n"),
           std::string("GET /api/status HTTP/1.1\r\nBad Header Line\r\n\r\n"),
           std::string("POST /api/capture HTTP/1.1\r\nContent-Length: nine\r\n\r\n"),
           std::string("POST /api/capture HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\nzz\r\n"),
       }) {
    // A second, valid request after the bad one must not be answered: the framing is lost.
    auto p = s.exchange(raw + get("/api/status"));
    ASSERT_EQ(p.responses.size(), 1u) << raw;
    EXPECT_EQ(p.responses[0].result(), http::status::bad_request) << raw;
    EXPECT_TRUE(isJson(p.responses[0]));
    EXPECT_NE(errorOf(p.responses[0]).find("malformed request"), std::string::npos) << raw;
    EXPECT_FALSE(p.responses[0].keep_alive());
  }
  // A request cut off by the client's end of stream is a malformed request, not a hang.
  auto cut = s.one("POST /api/capture HTTP/1.1\r\nContent-Length: 50\r\n\r\n{\"sku\"");
  EXPECT_EQ(cut.result(), http::status::bad_request);
}

TEST(HttpSession, OversizeBodyAndHeadersAreRefusedBeforeTheyAreRead) {
  SessionRig s("", 4096);
  // The declared length alone is refused: the 10 MB are never sent.
  auto r = s.one("POST /api/capture HTTP/1.1\r\nHost: t\r\nContent-Length: 10000000\r\n\r\n");
  EXPECT_EQ(r.result(), http::status::payload_too_large);
  EXPECT_NE(errorOf(r).find("4096 bytes"), std::string::npos) << r.body();
  // A chunked body that grows past the limit is cut off too.
  std::string chunked =
      "POST /api/capture HTTP/1.1\r\nHost: t\r\nTransfer-Encoding: chunked\r\n\r\n";
  for (int i = 0; i < 5; ++i)
    chunked += "400\r\n" + std::string(1024, 'x') + "\r\n";
  chunked += "0\r\n\r\n";
  EXPECT_EQ(s.one(chunked).result(), http::status::payload_too_large);
  auto big = s.one(get("/api/status", "X-Filler: " + std::string(20000, 'a') + "\r\n"));
  EXPECT_EQ(big.result(), http::status::request_header_fields_too_large);
  EXPECT_TRUE(isJson(big));
  // Just under the limit is fine (and reaches the handler, which refuses the unknown field).
  auto under =
      s.one(withBody("POST", "/api/capture", "{\"x\": \"" + std::string(4000, 'y') + "\"}"));
  EXPECT_EQ(under.result(), http::status::bad_request);
  EXPECT_NE(errorOf(under).find("unknown field 'x'"), std::string::npos);
}

TEST(HttpSession, TokenGuardsApiAndStreamsButNotTheUi) {
  SessionRig s(kToken);
  auto none = s.one(get("/api/status"));
  EXPECT_EQ(none.result(), http::status::unauthorized);
  EXPECT_EQ(none[http::field::www_authenticate], "Bearer realm=\"garmcapd\"");
  EXPECT_NE(errorOf(none).find("token"), std::string::npos);
  for (const std::string& bad :
       {std::string("Authorization: Bearer wrong\r\n"),
        std::string("Authorization: Bearer ") + kToken + "x\r\n",
        std::string("Authorization: Bearer ") + std::string(kToken).substr(1) + "\r\n",
        std::string("Authorization: Basic ") + kToken + "\r\n",
        std::string("Authorization: bearer") + kToken + "\r\n"})
    EXPECT_EQ(s.one(get("/api/status", bad)).result(), http::status::unauthorized) << bad;
  EXPECT_EQ(
      s.one(get("/api/status", std::string("Authorization: Bearer ") + kToken + "\r\n")).result(),
      http::status::ok);
  // ?token= is for GETs only (EventSource, <img>): it never authorizes a state change.
  EXPECT_EQ(s.one(get(std::string("/api/status?token=") + kToken)).result(), http::status::ok);
  EXPECT_EQ(s.one(withBody("POST", std::string("/api/button?token=") + kToken, "")).result(),
            http::status::unauthorized);
  EXPECT_EQ(s.one(get("/stream.mjpg")).result(), http::status::unauthorized);
  EXPECT_EQ(s.one(get("/api/events")).result(), http::status::unauthorized);
  // The UI's files hold no data: served without the token.
  EXPECT_EQ(s.one(get("/")).result(), http::status::ok);
}

TEST(HttpSession, PathTraversalNeverReachesTheFileSystem) {
  SessionRig s;
  for (const char* target : {
           "/../secret.txt",
           "/%2e%2e/secret.txt",
           "/img/../../secret.txt",
           "/img/..%2f..%2fsecret.txt",
           "//secret.txt",
           "/img//logo.svg",
           "/.%2e/secret.txt",
           "/index.html%00.png",
           "/api/items/1/images/..",
           "/api/items/1/images/../../catalog.sqlite",
           "/api/items/1/images/%2e%2e%2fcatalog.sqlite",
           "/api/items/1/images/cutout%2f..%2f..",
           "/api/items/..%2f1/images/cutout",
           "/api/items/1/pattern.json/../../../etc/passwd",
       }) {
    auto r = s.one(get(target));
    EXPECT_EQ(r.result(), http::status::not_found) << target;
    EXPECT_TRUE(isJson(r)) << target;
    EXPECT_EQ(r.body().find("outside the web folder"), std::string::npos) << target;
  }
  EXPECT_EQ(s.one(get("/img/logo.svg")).result(), http::status::ok);
}

TEST(HttpSession, MalformedJsonInPatchNamesTheProblem) {
  SessionRig s;
  auto r = s.one(withBody("PATCH", "/api/items/1", "{\"title\": \"x\",\n \"notes\": }"));
  EXPECT_EQ(r.result(), http::status::bad_request);
  const std::string e = errorOf(r);
  EXPECT_NE(e.find("malformed JSON"), std::string::npos) << e;
  EXPECT_NE(e.find("line 2"), std::string::npos) << e;
  auto notObject = s.one(withBody("PATCH", "/api/items/1", "[1, 2]"));
  EXPECT_NE(errorOf(notObject).find("must be a JSON object"), std::string::npos);
  auto wrongType = s.one(withBody("PATCH", "/api/items/1", R"({"title": 5})"));
  EXPECT_NE(errorOf(wrongType).find("field 'title' must be a string"), std::string::npos);
  auto badValue =
      s.one(withBody("PATCH", "/api/items/1", R"({"measurements": {"bust_circ": -3}})"));
  EXPECT_NE(errorOf(badValue).find("bust_circ"), std::string::npos);
  auto empty = s.one(withBody("PATCH", "/api/items/1", ""));
  EXPECT_EQ(empty.result(), http::status::bad_request);
  EXPECT_NE(errorOf(empty).find("malformed JSON"), std::string::npos);
  // Valid JSON on an item that does not exist: 404, not 400.
  EXPECT_EQ(s.one(withBody("PATCH", "/api/items/7", R"({"title": "x"})")).result(),
            http::status::not_found);
}

TEST(HttpSession, UnknownRoutesAndMethodsAreJsonErrors) {
  SessionRig s;
  auto r = s.one(get("/api/nothing/here"));
  EXPECT_EQ(r.result(), http::status::not_found);
  EXPECT_TRUE(isJson(r));
  EXPECT_EQ(errorOf(r), "no such resource");
  auto page = s.one(get("/no-such-page.html"));
  EXPECT_EQ(page.result(), http::status::not_found);
  EXPECT_TRUE(isJson(page));
  auto method = s.one(withBody("PUT", "/api/status", "{}"));
  EXPECT_EQ(method.result(), http::status::method_not_allowed);
  EXPECT_NE(errorOf(method).find("PUT"), std::string::npos);
  EXPECT_EQ(s.one(withBody("POST", "/index.html", "{}")).result(),
            http::status::method_not_allowed);
  EXPECT_EQ(s.one(get("/api/items/abc")).result(), http::status::bad_request);
  EXPECT_EQ(s.one(get("/api/items/99999999999999999999")).result(), http::status::bad_request);
  EXPECT_EQ(s.one(get("/api/items?limit=-1")).result(), http::status::bad_request);
  EXPECT_EQ(s.one(get("/" + std::string(3000, 'a'))).result(), http::status::not_found);
}

TEST(HttpSession, EventStreamStartsWithTheStatus) {
  SessionRig s;
  const std::string got = s.streamUntil(get("/api/events"), "event: status");
  EXPECT_EQ(got.rfind("HTTP/1.1 200 OK\r\n", 0), 0u) << got;
  EXPECT_NE(got.find("text/event-stream"), std::string::npos) << got;
}

}  // namespace
}  // namespace garmcap::daemon

namespace garmcap::daemon {
namespace {

struct Victim : Evictable {
  int evicted = 0;
  void evict() override { ++evicted; }
};

TEST(ClientConnections, EachAddressHoldsAtMostItsLimitAndGetsItsSlotsBack) {
  ClientConnections clients;
  std::vector<ClientConnections::Slot> a;
  for (int i = 0; i < 3; ++i) {
    auto s = clients.acquire("10.0.0.2", 3);
    ASSERT_TRUE(s);
    a.push_back(std::move(*s));
  }
  EXPECT_FALSE(clients.acquire("10.0.0.2", 3));
  EXPECT_TRUE(clients.acquire("10.0.0.3", 3)) << "another address is not limited by the first";
  EXPECT_EQ(clients.count("10.0.0.2"), 3);
  EXPECT_TRUE(clients.acquire("10.0.0.2", 3, /*force=*/true));  // released again at once
  a.pop_back();
  EXPECT_EQ(clients.count("10.0.0.2"), 2);
  EXPECT_TRUE(clients.acquire("10.0.0.2", 3));
  a.clear();
  EXPECT_EQ(clients.count("10.0.0.2"), 0);
}

TEST(WaitingSessions, EvictsTheOldestOfOneClientOrOfAll) {
  WaitingSessions waiting;
  auto first = std::make_shared<Victim>(), second = std::make_shared<Victim>(),
       third = std::make_shared<Victim>();
  waiting.add(first, "10.0.0.2");
  waiting.add(second, "10.0.0.3");
  waiting.add(third, "10.0.0.3");
  EXPECT_TRUE(waiting.evictOldest(std::string("10.0.0.3")));
  EXPECT_EQ(first->evicted, 0);
  EXPECT_EQ(second->evicted, 1);
  EXPECT_FALSE(waiting.evictOldest(std::string("10.0.0.9")));
  EXPECT_TRUE(waiting.evictOldest());
  EXPECT_EQ(first->evicted, 1);
  EXPECT_EQ(third->evicted, 0);
  third.reset();  // a session that is gone is skipped, not evicted
  EXPECT_FALSE(waiting.evictOldest());
}

}  // namespace
}  // namespace garmcap::daemon
