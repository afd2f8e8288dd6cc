// The request checks every request passes before routing (http_guard.h): UTF-8, echoing input,
// Host (DNS rebinding), Origin and content type on writes (CSRF), long targets; and the
// browser log-in sessions (login_sessions.h).

#include "garmcap/daemon/http_guard.h"

#include <gtest/gtest.h>

#include "garmcap/daemon/login_sessions.h"

namespace garmcap::daemon {
namespace {

Request request(http::verb verb, const std::string& target, const std::string& host,
                const std::string& body = "", const std::string& type = "",
                const std::string& origin = "") {
  Request r{verb, target, 11};
  if (!host.empty())
    r.set(http::field::host, host);
  if (!type.empty())
    r.set(http::field::content_type, type);
  if (!origin.empty())
    r.set(http::field::origin, origin);
  r.body() = body;
  r.prepare_payload();
  return r;
}

TEST(Utf8, AcceptsWellFormedAndRefusesEachKindOfMalformed) {
  EXPECT_TRUE(validUtf8(""));
  EXPECT_TRUE(validUtf8("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x91\x97"));  // é € 👗
  EXPECT_FALSE(validUtf8("caf\xff"));
  EXPECT_FALSE(validUtf8("\xc0\xaf"));          // overlong '/'
  EXPECT_FALSE(validUtf8("\xe0\x80\xaf"));      // overlong, three bytes
  EXPECT_FALSE(validUtf8("\xed\xa0\x80"));      // a UTF-16 surrogate
  EXPECT_FALSE(validUtf8("\xf4\x90\x80\x80"));  // past U+10FFFF
  EXPECT_FALSE(validUtf8("\xc3"));              // cut short
  EXPECT_FALSE(validUtf8("\x80"));              // a lone continuation byte
}

TEST(QuoteInput, EscapesBadBytesAndControlsAndCutsAtACharacter) {
  EXPECT_EQ(quoteInput("caf\xff"), "caf\\xff");
  EXPECT_EQ(quoteInput(std::string("a\0b", 3)), "a\\x00b");
  EXPECT_EQ(quoteInput("caf\xc3\xa9"), "caf\xc3\xa9");
  const std::string cut = quoteInput(std::string(100, 'x'), 10);
  EXPECT_EQ(cut, std::string(10, 'x') + "...");
  EXPECT_TRUE(validUtf8(quoteInput("\xe2\x82\xac\xe2\x82\xac\xe2\x82\xac", 4)));
}

TEST(HostCheck, IpLiteralsLocalhostAndConfiguredNamesOnly) {
  const std::vector<std::string> names = {"Station.local"};
  EXPECT_TRUE(hostAllowed("127.0.0.1:8080", names));
  EXPECT_TRUE(hostAllowed("192.168.1.20", names));
  EXPECT_TRUE(hostAllowed("[::1]:8080", names));
  EXPECT_TRUE(hostAllowed("localhost:8080", names));
  EXPECT_TRUE(hostAllowed("station.LOCAL:8080", names));
  EXPECT_FALSE(hostAllowed("evil.example:8080", names));       // DNS rebinding
  EXPECT_FALSE(hostAllowed("127.0.0.1.evil.example", names));  // not an IP literal
  EXPECT_FALSE(hostAllowed("", names));
  EXPECT_FALSE(hostAllowed("127.0.0.1:80x", names));
  EXPECT_FALSE(hostAllowed("[::1", names));
}

TEST(RefuseRequest, LongTargetIs414) {
  auto r = refuseRequest(
      request(http::verb::get, "/api/items?q=" + std::string(9000, 'a'), "127.0.0.1"), {});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, http::status::uri_too_long);
  EXPECT_FALSE(refuseRequest(
      request(http::verb::get, "/api/items?q=" + std::string(4000, 'a'), "127.0.0.1"), {}));
}

TEST(RefuseRequest, ForeignHostIs403NamingIt) {
  auto r = refuseRequest(request(http::verb::get, "/api/items", "rebind.example"), {});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, http::status::forbidden);
  EXPECT_NE(r->message.find("rebind.example"), std::string::npos);
  EXPECT_NE(r->message.find("server_names"), std::string::npos);
}

TEST(RefuseRequest, CrossOriginWritesAre403SameOriginPass) {
  const std::string body = R"({"sku": "A1"})";
  auto cross = refuseRequest(request(http::verb::post, "/api/capture", "127.0.0.1:8080", body,
                                     "application/json", "http://evil.example"),
                             {});
  ASSERT_TRUE(cross);
  EXPECT_EQ(cross->status, http::status::forbidden);
  EXPECT_FALSE(refuseRequest(request(http::verb::post, "/api/capture", "127.0.0.1:8080", body,
                                     "application/json", "http://127.0.0.1:8080"),
                             {}));
  // Reads may come from anywhere the Host check lets through (an <img> of the UI).
  EXPECT_FALSE(refuseRequest(
      request(http::verb::get, "/api/items", "127.0.0.1:8080", "", "", "http://evil.example"), {}));
  // A sandboxed page sends "Origin: null".
  EXPECT_TRUE(refuseRequest(
      request(http::verb::post, "/api/button", "127.0.0.1:8080", "", "", "null"), {}));
}

TEST(RefuseRequest, WriteBodiesMustBeJson) {
  auto plain = refuseRequest(
      request(http::verb::post, "/api/capture", "127.0.0.1", R"({"sku": "A1"})", "text/plain"), {});
  ASSERT_TRUE(plain);
  EXPECT_EQ(plain->status, http::status::unsupported_media_type);
  EXPECT_FALSE(refuseRequest(request(http::verb::patch, "/api/items/1", "127.0.0.1", "{}",
                                     "Application/JSON; charset=utf-8"),
                             {}));
  // No body, no type needed (curl -X POST /api/button).
  EXPECT_FALSE(refuseRequest(request(http::verb::post, "/api/button", "127.0.0.1"), {}));
  // Raw bytes only with PUT (the hub's blobs), never with the other writes.
  EXPECT_FALSE(refuseRequest(request(http::verb::put, "/api/hub/blobs/x", "127.0.0.1", "\x89PNG",
                                     "application/octet-stream"),
                             {}));
  for (auto verb : {http::verb::post, http::verb::patch, http::verb::delete_}) {
    auto raw = refuseRequest(
        request(verb, "/api/hub/push", "127.0.0.1", "\x89PNG", "application/octet-stream"), {});
    ASSERT_TRUE(raw);
    EXPECT_EQ(raw->status, http::status::unsupported_media_type);
  }
  auto form = refuseRequest(request(http::verb::put, "/api/hub/blobs/x", "127.0.0.1", "a=b",
                                    "application/x-www-form-urlencoded"),
                            {});
  ASSERT_TRUE(form);
  EXPECT_EQ(form->status, http::status::unsupported_media_type);
}

}  // namespace
}  // namespace garmcap::daemon

namespace garmcap::daemon {
namespace {

TEST(LoginSessions, IdsAreRandomLiveUntilRevokedOrExpired) {
  LoginSessions s(std::chrono::seconds(3600), 3);
  const std::string a = s.create(), b = s.create();
  EXPECT_EQ(a.size(), 64u);
  EXPECT_NE(a, b);
  EXPECT_TRUE(s.valid(a));
  EXPECT_FALSE(s.valid(std::string(64, '0')));
  EXPECT_FALSE(s.valid(a.substr(0, 63)));
  s.revoke(a);
  EXPECT_FALSE(s.valid(a));
  EXPECT_TRUE(s.valid(b));
  // Past the cap the oldest gives way.
  const std::string c = s.create(), d = s.create(), e = s.create();
  EXPECT_FALSE(s.valid(b));
  EXPECT_TRUE(s.valid(c) && s.valid(d) && s.valid(e));
  LoginSessions shortLived(std::chrono::seconds(0));
  EXPECT_FALSE(shortLived.valid(shortLived.create()));
}

TEST(LoginSessions, CookieValueFindsTheNamedCookie) {
  EXPECT_EQ(cookieValue("a=1; garmcap_session=abc; b=2", kSessionCookie).value_or(""), "abc");
  EXPECT_EQ(cookieValue("garmcap_session=x", kSessionCookie).value_or(""), "x");
  EXPECT_FALSE(cookieValue("xgarmcap_session=abc", kSessionCookie));
  EXPECT_FALSE(cookieValue("", kSessionCookie));
}

}  // namespace
}  // namespace garmcap::daemon
