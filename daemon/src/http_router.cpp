#include "garmcap/daemon/http_router.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "garmcap/daemon/disk_full.h"
#include "garmcap/daemon/http_guard.h"
#include "garmcap/drafts/file_io.h"

namespace garmcap::daemon {

namespace {

constexpr std::size_t kMaxParamLength = 64;

bool isParamChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '-';
}

std::vector<std::string_view> splitPath(std::string_view path) {
  std::vector<std::string_view> out;
  std::size_t start = 1;  // skip the leading '/'
  while (start <= path.size()) {
    const std::size_t slash = path.find('/', start);
    const std::size_t end = slash == std::string_view::npos ? path.size() : slash;
    out.push_back(path.substr(start, end - start));
    if (slash == std::string_view::npos)
      break;
    start = slash + 1;
  }
  return out;
}

int hexValue(char c) {
  if (c >= '0' && c <= '9')
    return c - '0';
  if (c >= 'a' && c <= 'f')
    return c - 'a' + 10;
  if (c >= 'A' && c <= 'F')
    return c - 'A' + 10;
  return -1;
}

std::optional<std::string> percentDecode(std::string_view in) {
  std::string out;
  out.reserve(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (in[i] == '+') {
      out.push_back(' ');
    } else if (in[i] == '%') {
      if (i + 2 >= in.size())
        return std::nullopt;
      const int hi = hexValue(in[i + 1]), lo = hexValue(in[i + 2]);
      if (hi < 0 || lo < 0)
        return std::nullopt;
      out.push_back(static_cast<char>(hi * 16 + lo));
      i += 2;
    } else {
      out.push_back(in[i]);
    }
  }
  return out;
}

void parseQuery(std::string_view query, RouteMatch& m) {
  std::size_t start = 0;
  while (start < query.size()) {
    std::size_t amp = query.find('&', start);
    if (amp == std::string_view::npos)
      amp = query.size();
    const std::string_view pair = query.substr(start, amp - start);
    const std::size_t eq = pair.find('=');
    auto key = percentDecode(pair.substr(0, eq));
    auto value = eq == std::string_view::npos ? std::optional<std::string>("")
                                              : percentDecode(pair.substr(eq + 1));
    start = amp + 1;
    // A name that does not decode cannot be asked for by a route: it is ignored like any
    // unknown parameter.
    if (!key || key->empty() || !validUtf8(*key))
      continue;
    if (!value)
      m.badQuery[*key] = "is not valid percent-encoding";
    else if (!validUtf8(*value))
      m.badQuery[*key] = "is not valid UTF-8";
    else if (std::any_of(value->begin(), value->end(),
                         [](unsigned char c) { return c < 0x20 || c == 0x7F; }))
      m.badQuery[*key] = "holds a control character";
    else
      m.query[*key] = *value;
  }
}

}  // namespace

// A compiled pattern: one entry per path segment.
struct Router::Route {
  struct Segment {
    std::string prefix;  // literal text (the whole segment when param is empty)
    std::string param;   // name of the captured value, empty for a literal segment
    std::string suffix;
  };
  http::verb verb;
  std::string pattern;
  std::vector<Segment> segments;
  Handler handler;
  StreamHandler stream;

  bool matchPath(const std::vector<std::string_view>& parts, RouteMatch& out) const {
    if (parts.size() != segments.size())
      return false;
    for (std::size_t i = 0; i < parts.size(); ++i) {
      const Segment& s = segments[i];
      const std::string_view p = parts[i];
      if (s.param.empty()) {
        if (p != s.prefix)
          return false;
        continue;
      }
      if (p.size() <= s.prefix.size() + s.suffix.size())
        return false;
      if (p.substr(0, s.prefix.size()) != s.prefix)
        return false;
      if (p.substr(p.size() - s.suffix.size()) != s.suffix)
        return false;
      const std::string_view value =
          p.substr(s.prefix.size(), p.size() - s.prefix.size() - s.suffix.size());
      if (value.size() > kMaxParamLength)
        return false;
      if (!std::all_of(value.begin(), value.end(), isParamChar))
        return false;
      out.params[s.param] = std::string(value);
    }
    return true;
  }
};

namespace {

std::shared_ptr<Router::Route> compile(http::verb verb, std::string pattern) {
  if (pattern.empty() || pattern[0] != '/')
    throw std::invalid_argument("route pattern must start with '/': " + pattern);
  auto route = std::make_shared<Router::Route>();
  route->verb = verb;
  route->pattern = pattern;
  for (std::string_view part : splitPath(pattern)) {
    Router::Route::Segment seg;
    const std::size_t open = part.find('{');
    if (open == std::string_view::npos) {
      seg.prefix = std::string(part);
    } else {
      const std::size_t close = part.find('}', open);
      if (close == std::string_view::npos || close == open + 1)
        throw std::invalid_argument("bad parameter in route pattern: " + pattern);
      seg.prefix = std::string(part.substr(0, open));
      seg.param = std::string(part.substr(open + 1, close - open - 1));
      seg.suffix = std::string(part.substr(close + 1));
    }
    route->segments.push_back(std::move(seg));
  }
  return route;
}

}  // namespace

std::int64_t RouteMatch::id(const std::string& name) const {
  const std::string& text = param(name);
  std::int64_t value = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || ptr != text.data() + text.size() || value <= 0)
    throw BadRequest("'" + name + "' must be a positive integer id, got '" + text + "'");
  return value;
}

const std::string& RouteMatch::param(const std::string& name) const {
  auto it = params.find(name);
  if (it == params.end())
    throw BadRequest("missing path parameter '" + name + "'");
  return it->second;
}

std::optional<std::string> RouteMatch::queryValue(const std::string& name) const {
  if (auto bad = badQuery.find(name); bad != badQuery.end())
    throw BadRequest("query '" + name + "' " + bad->second);
  auto it = query.find(name);
  if (it == query.end())
    return std::nullopt;
  return it->second;
}

void Router::add(http::verb verb, std::string pattern, Handler handler) {
  auto route = compile(verb, std::move(pattern));
  route->handler = std::move(handler);
  routes_.push_back(std::move(route));
}

void Router::addStream(http::verb verb, std::string pattern, StreamHandler handler) {
  auto route = compile(verb, std::move(pattern));
  route->stream = std::move(handler);
  routes_.push_back(std::move(route));
}

Router::Match Router::find(http::verb verb, std::string_view target) const {
  Match result;
  if (target.empty() || target.size() > kMaxTargetBytes || target[0] != '/')
    return result;
  const std::size_t q = target.find('?');
  const std::string_view path = target.substr(0, q);
  const auto parts = splitPath(path);
  for (const auto& route : routes_) {
    RouteMatch m;
    if (!route->matchPath(parts, m))
      continue;
    const bool verbOk = route->verb == verb || (verb == http::verb::head &&
                                                route->verb == http::verb::get && route->handler);
    if (!verbOk) {
      result.pathMatched = true;
      continue;
    }
    if (q != std::string_view::npos)
      parseQuery(target.substr(q + 1), m);
    result.match = std::move(m);
    result.handler = route->handler ? &route->handler : nullptr;
    result.stream = route->stream ? &route->stream : nullptr;
    result.pathMatched = true;
    return result;
  }
  return result;
}

void Router::dispatch(const Request& request, Reply reply) const {
  const auto target = request.target();
  Match m = find(request.method(), std::string_view(target.data(), target.size()));
  if (!m.handler) {
    if (m.stream) {
      reply(jsonError(http::status::bad_request, "this resource is a stream"));
    } else if (m.pathMatched) {
      reply(jsonError(http::status::method_not_allowed,
                      "method " + std::string(request.method_string()) + " not allowed here"));
    } else {
      reply(jsonError(http::status::not_found, "no such resource"));
    }
    return;
  }
  try {
    (*m.handler)(request, m.match, reply);
  } catch (const BadRequest& e) {
    reply(jsonError(http::status::bad_request, e.what()));
  } catch (const DiskFull& e) {
    spdlog::error("http: {}", e.what());
    reply(jsonError(http::status::insufficient_storage, e.what()));
  } catch (const std::exception& e) {
    // The details (SQL text, paths) go to the log, not to the client.
    spdlog::error("http: {} {} failed: {}", std::string(request.method_string()),
                  quoteInput(std::string_view(target.data(), target.size()), 200), e.what());
    reply(jsonError(http::status::internal_server_error,
                    "internal error; the station's log has the details"));
  } catch (...) {
    spdlog::error("http: {} {} failed with a non-standard exception",
                  std::string(request.method_string()),
                  quoteInput(std::string_view(target.data(), target.size()), 200));
    reply(jsonError(http::status::internal_server_error,
                    "internal error; the station's log has the details"));
  }
}

Response jsonResponse(http::status status, const nlohmann::json& body) {
  Response res{status, 11};
  res.set(http::field::content_type, "application/json");
  res.set(http::field::cache_control, "no-store");
  // Replace, never throw: a message quoting a client's invalid UTF-8 must not take the daemon
  // down (nlohmann's default throws type_error.316 from dump()).
  res.body() = body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  res.prepare_payload();
  return res;
}

Response jsonError(http::status status, const std::string& message) {
  return jsonResponse(status, nlohmann::json{{"error", message}});
}

void replyFailure(const Reply& failed, const std::string& what, std::exception_ptr error) {
  try {
    std::rethrow_exception(error);
  } catch (const BadRequest& e) {
    if (failed)
      failed(jsonError(http::status::bad_request, e.what()));
    return;
  } catch (const DiskFull& e) {
    spdlog::error("station: {} failed: {}", what, e.what());
    if (failed)
      failed(jsonError(http::status::insufficient_storage, e.what()));
    return;
  } catch (const std::exception& e) {
    spdlog::error("station: {} failed: {}", what, e.what());
  } catch (...) {
    spdlog::error("station: {} failed with a non-standard exception", what);
  }
  if (failed)
    failed(jsonError(http::status::internal_server_error,
                     "internal error; the station's log has the details"));
}

Response textResponse(http::status status, std::string contentType, std::string body) {
  Response res{status, 11};
  res.set(http::field::content_type, contentType);
  res.body() = std::move(body);
  res.prepare_payload();
  return res;
}

nlohmann::json parseJsonBody(const Request& request) {
  try {
    return drafts::parseJson(request.body(), "request body");
  } catch (const std::exception& e) {
    throw BadRequest("malformed JSON body: " + quoteInput(e.what(), 300));
  }
}

// --- static files ---------------------------------------------------------------------------

StaticFiles::StaticFiles(std::string webDir) : dir_(std::move(webDir)) {
  rescan();
}

std::optional<std::string> StaticFiles::contentType(std::string_view fileName) {
  static const std::map<std::string, std::string, std::less<>> kTypes = {
      {"html", "text/html; charset=utf-8"},
      {"js", "text/javascript; charset=utf-8"},
      {"mjs", "text/javascript; charset=utf-8"},
      {"css", "text/css; charset=utf-8"},
      {"svg", "image/svg+xml"},
      {"png", "image/png"},
      {"jpg", "image/jpeg"},
      {"jpeg", "image/jpeg"},
      {"webp", "image/webp"},
      {"ico", "image/x-icon"},
      {"json", "application/json"},
      {"txt", "text/plain; charset=utf-8"},
      {"woff2", "font/woff2"},
      {"map", "application/json"},
  };
  const std::size_t dot = fileName.rfind('.');
  if (dot == std::string_view::npos)
    return std::nullopt;
  auto it = kTypes.find(fileName.substr(dot + 1));
  if (it == kTypes.end())
    return std::nullopt;
  return it->second;
}

void StaticFiles::rescan() {
  namespace fs = std::filesystem;
  std::map<std::string, std::pair<std::string, std::string>> files;
  std::error_code ec;
  if (!dir_.empty() && fs::is_directory(dir_, ec)) {
    fs::recursive_directory_iterator it(dir_, fs::directory_options::none, ec), end;
    for (; !ec && it != end; it.increment(ec)) {
      const fs::path rel = fs::relative(it->path(), dir_, ec);
      bool ok = !ec;
      for (const auto& part : rel) {
        const std::string s = part.string();
        ok = ok && !s.empty() && s[0] != '.' &&
             std::all_of(s.begin(), s.end(), [](char c) { return isParamChar(c) || c == '.'; });
      }
      if (!ok) {
        if (it->is_directory(ec))
          it.disable_recursion_pending();
        continue;
      }
      if (!it->is_regular_file(ec) || it->is_symlink(ec))
        continue;
      auto type = contentType(rel.filename().string());
      if (!type)
        continue;
      files["/" + rel.generic_string()] = {it->path().string(), *type};
    }
  }
  files_ = std::move(files);
  spdlog::info("http: serving {} static files from {}", files_.size(), dir_);
}

std::optional<Response> StaticFiles::serve(std::string_view path, unsigned version,
                                           bool keepAlive) const {
  std::string key(path.substr(0, path.find('?')));
  if (key == "/")
    key = "/index.html";
  auto it = files_.find(key);
  if (it == files_.end())
    return std::nullopt;
  std::ifstream in(it->second.first, std::ios::binary);
  if (!in)
    return std::nullopt;
  std::ostringstream body;
  body << in.rdbuf();
  Response res{http::status::ok, version};
  res.set(http::field::content_type, it->second.second);
  res.set(http::field::cache_control, "no-cache");
  res.set("X-Content-Type-Options", "nosniff");
  res.keep_alive(keepAlive);
  res.body() = body.str();
  res.prepare_payload();
  return res;
}

}  // namespace garmcap::daemon
