#include "garmcap/daemon/http_guard.h"

#include <algorithm>
#include <cctype>

namespace garmcap::daemon {

namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

bool isIpv4Literal(std::string_view h) {
  int parts = 0, digits = 0, value = 0;
  for (char c : h) {
    if (c == '.') {
      if (digits == 0)
        return false;
      ++parts, digits = 0, value = 0;
    } else if (c >= '0' && c <= '9') {
      value = value * 10 + (c - '0');
      if (++digits > 3 || value > 255)
        return false;
    } else {
      return false;
    }
  }
  return digits > 0 && parts == 3;
}

// "scheme://host[:port]" of an Origin header: its host[:port], or empty.
std::string_view originAuthority(std::string_view origin) {
  const std::size_t sep = origin.find("://");
  if (sep == std::string_view::npos)
    return {};
  return origin.substr(sep + 3);
}

}  // namespace

std::string hostName(std::string_view hostHeader) {
  std::string_view h = hostHeader;
  if (h.empty())
    return {};
  if (h.front() == '[') {
    const std::size_t close = h.find(']');
    if (close == std::string_view::npos)
      return {};
    const std::string_view rest = h.substr(close + 1);
    if (!rest.empty() && rest.front() != ':')
      return {};
    return lower(h.substr(0, close + 1));
  }
  const std::size_t colon = h.find(':');
  const std::string_view name = h.substr(0, colon);
  if (colon != std::string_view::npos) {
    const std::string_view port = h.substr(colon + 1);
    if (port.empty() || port.size() > 5 ||
        !std::all_of(port.begin(), port.end(), [](char c) { return c >= '0' && c <= '9'; }))
      return {};
  }
  if (name.empty() || !std::all_of(name.begin(), name.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' || c == '_';
      }))
    return {};
  return lower(name);
}

bool hostAllowed(std::string_view hostHeader, const std::vector<std::string>& serverNames) {
  const std::string name = hostName(hostHeader);
  if (name.empty())
    return false;
  if (name.front() == '[' || isIpv4Literal(name) || name == "localhost")
    return true;
  return std::any_of(serverNames.begin(), serverNames.end(),
                     [&](const std::string& allowed) { return lower(allowed) == name; });
}

std::optional<Refusal> refuseRequest(const Request& request,
                                     const std::vector<std::string>& serverNames) {
  const auto target = request.target();
  const std::string_view t(target.data(), target.size());
  if (t.size() > kMaxTargetBytes)
    return Refusal{http::status::uri_too_long,
                   "request target longer than " + std::to_string(kMaxTargetBytes) + " bytes"};
  if (!validUtf8(t) || std::any_of(t.begin(), t.end(), [](unsigned char c) { return c < 0x21; }))
    return Refusal{http::status::bad_request, "request target holds bytes not allowed in a URL"};
  const auto hostField = request[http::field::host];
  const std::string_view host(hostField.data(), hostField.size());
  if (!hostAllowed(host, serverNames))
    return Refusal{http::status::forbidden,
                   "host '" + quoteInput(host) +
                       "' is not a name of this station (add it to [http] server_names)"};
  const auto method = request.method();
  const bool write = method == http::verb::post || method == http::verb::put ||
                     method == http::verb::patch || method == http::verb::delete_;
  if (!write)
    return std::nullopt;
  const auto originField = request[http::field::origin];
  if (!originField.empty()) {
    const std::string_view origin(originField.data(), originField.size());
    if (lower(originAuthority(origin)) != lower(host))
      return Refusal{http::status::forbidden, "cross-origin write from '" + quoteInput(origin) +
                                                  "' refused (the web UI of this station only)"};
  }
  if (!request.body().empty()) {
    const auto typeField = request[http::field::content_type];
    const std::string type = lower(std::string_view(typeField.data(), typeField.size()));
    std::string_view media = std::string_view(type).substr(0, type.find(';'));
    while (!media.empty() && media.back() == ' ')
      media.remove_suffix(1);
    while (!media.empty() && media.front() == ' ')
      media.remove_prefix(1);
    // A PUT may carry raw bytes (the hub's blobs): a cross-origin page cannot send a PUT, nor
    // this type, without a preflight that nothing here answers.
    const bool rawPut = method == http::verb::put && media == "application/octet-stream";
    if (media != "application/json" && !rawPut)
      return Refusal{http::status::unsupported_media_type,
                     "a request body must be application/json, got '" +
                         quoteInput(std::string_view(typeField.data(), typeField.size())) + "'"};
  }
  return std::nullopt;
}

}  // namespace garmcap::daemon
