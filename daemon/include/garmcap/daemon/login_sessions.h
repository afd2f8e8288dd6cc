#pragma once
// Browser log-in for a station with a token: the token is given once (POST /api/session) and
// exchanged for a random session id in an HttpOnly, SameSite=Strict cookie. The browser then
// sends it on everything the UI loads by itself (EventSource, <img>, the MJPEG preview,
// downloads), none of which can carry an Authorization header; the token itself never sits in
// the page's storage. Sessions live in memory: a restart asks for the token again.

#include <chrono>
#include <cstddef>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

namespace garmcap::daemon {

inline constexpr std::string_view kSessionCookie = "garmcap_session";

class LoginSessions {
 public:
  using Clock = std::chrono::steady_clock;
  explicit LoginSessions(std::chrono::seconds lifetime = std::chrono::hours(24 * 30),
                         std::size_t maxSessions = 256)
      : lifetime_(lifetime), maxSessions_(maxSessions) {}

  /// A new session id (256 bits from the kernel's CSPRNG, hex). The oldest session gives way
  /// past `maxSessions`.
  std::string create();
  /// True for a live session id (constant time in the id's length).
  bool valid(std::string_view id) const;
  void revoke(std::string_view id);
  std::chrono::seconds lifetime() const { return lifetime_; }

 private:
  std::chrono::seconds lifetime_;
  std::size_t maxSessions_;
  mutable std::mutex mutex_;
  std::map<std::string, Clock::time_point, std::less<>> sessions_;  // id -> expiry
};

/// The value of cookie `name` in a Cookie header ("a=1; garmcap_session=...").
std::optional<std::string_view> cookieValue(std::string_view header, std::string_view name);

/// Constant-time equality (no early exit on the first differing byte).
bool constantTimeEqual(std::string_view a, std::string_view b);

}  // namespace garmcap::daemon
