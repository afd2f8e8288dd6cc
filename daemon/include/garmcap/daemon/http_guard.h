#pragma once
// What every request must satisfy before any route sees it, and how input is echoed back.
//
// A station on the shop's network is reachable by every browser on it: a web page can send
// requests from an <img> or a form (CSRF), and a DNS name of the attacker's that resolves to the
// station reads its API through the visitor's browser (DNS rebinding). The checks here close both
// without a token on loopback. They are pure functions so that they are tested apart from the
// server (tests/daemon/http_guard_test.cpp) and the session only calls them.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "garmcap/daemon/http_router.h"
#include "garmcap/daemon/utf8.h"

namespace garmcap::daemon {

/// Longest request target answered; longer ones get 414 (the header limit is 16 KiB).
inline constexpr std::size_t kMaxTargetBytes = 8192;

/// The host part of a Host header (no port; IPv6 literals keep their brackets); empty when the
/// header is malformed.
std::string hostName(std::string_view hostHeader);

/// A Host header the station answers to: an IP literal (a DNS-rebinding attack needs a name),
/// "localhost", or one of `serverNames` (case-insensitive). An empty Host is refused (HTTP/1.1
/// requires it).
bool hostAllowed(std::string_view hostHeader, const std::vector<std::string>& serverNames);

/// Why a request is refused before routing, if it is.
struct Refusal {
  http::status status;
  std::string message;
};

/// The checks in order: target length (414), target bytes (400), Host (403), and for state-
/// changing methods (POST, PUT, PATCH, DELETE) a cross-origin Origin (403: a browser always sends
/// Origin on a cross-origin write) and a body that is not application/json (415: the only body a
/// write takes, and one a cross-origin form cannot send without a preflight), except that a PUT
/// may send application/octet-stream (the hub's blobs; neither needs less than a preflight).
std::optional<Refusal> refuseRequest(const Request& request,
                                     const std::vector<std::string>& serverNames);

}  // namespace garmcap::daemon
