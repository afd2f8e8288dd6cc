// libFuzzer: raw bytes as an HTTP request, through everything garmcapd does with a request before
// a handler runs: Beast's parser (the session's limits), the pre-routing checks, the token and
// cookie check, the router's path and query decoding, the JSON body parser, and the error answer.
// Properties checked besides "no crash, no sanitizer finding": whatever is quoted back is valid
// UTF-8, and every JSON answer serializes.

#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "garmcap/daemon/http_guard.h"
#include "garmcap/daemon/http_router.h"
#include "garmcap/daemon/http_server.h"
#include "garmcap/daemon/login_sessions.h"

using namespace garmcap::daemon;
namespace beast = boost::beast;

namespace {

const Router& router() {
  static Router r = [] {
    Router x;
    auto echo = [](const Request& req, const RouteMatch& m, Reply reply) {
      for (const char* q : {"limit", "q", "size", "base_url", "offset"})
        if (auto v = m.queryValue(q); v && !validUtf8(*v))
          std::abort();  // a decoded query value must be valid UTF-8
      if (!req.body().empty())
        (void)parseJsonBody(req);
      reply(jsonResponse(http::status::ok, {{"id", m.params.count("id") ? m.id("id") : 0}}));
    };
    x.add(http::verb::get, "/api/items", echo);
    x.add(http::verb::get, "/api/items/{id}", echo);
    x.add(http::verb::patch, "/api/items/{id}", echo);
    x.add(http::verb::get, "/api/items/{id}/pattern.json", echo);
    x.add(http::verb::get, "/api/export/{name}.csv", echo);
    x.add(http::verb::post, "/api/capture", echo);
    return x;
  }();
  return r;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  if (!validUtf8(quoteInput(bytes, 200)))
    std::abort();
  http::request_parser<http::string_body> parser;
  parser.header_limit(16 * 1024);
  parser.body_limit(1 << 20);
  parser.eager(true);
  beast::error_code ec;
  parser.put(boost::asio::buffer(bytes.data(), bytes.size()), ec);
  if (ec || !parser.is_done())
    return 0;
  const Request req = parser.release();
  static LoginSessions logins;
  (void)authorized(req, "fuzz-token-0123456789", &logins);
  if (auto refusal = refuseRequest(req, {"station.local"})) {
    (void)jsonError(refusal->status, refusal->message);
    return 0;
  }
  router().dispatch(req, [](Response res) {
    if (res.body().empty())
      std::abort();  // every answer of the router is a JSON document
  });
  return 0;
}
