#include "garmcap/daemon/login_sessions.h"

#include <sys/random.h>

#include <stdexcept>

namespace garmcap::daemon {

bool constantTimeEqual(std::string_view a, std::string_view b) {
  unsigned diff = a.size() == b.size() ? 0u : 1u;
  for (std::size_t i = 0; i < b.size(); ++i)
    diff |= static_cast<unsigned>(b[i] ^ (i < a.size() ? a[i] : 0));
  return diff == 0;
}

std::string LoginSessions::create() {
  unsigned char bytes[32];
  std::size_t got = 0;
  while (got < sizeof bytes) {
    const ssize_t n = getrandom(bytes + got, sizeof bytes - got, 0);
    if (n < 0)
      throw std::runtime_error("login: the kernel gave no random bytes for a session id");
    got += static_cast<std::size_t>(n);
  }
  static const char kHex[] = "0123456789abcdef";
  std::string id;
  for (unsigned char b : bytes) {
    id += kHex[b >> 4];
    id += kHex[b & 0xF];
  }
  std::lock_guard lock(mutex_);
  const auto now = Clock::now();
  std::erase_if(sessions_, [&](const auto& s) { return s.second <= now; });
  while (sessions_.size() >= maxSessions_) {
    auto oldest = sessions_.begin();
    for (auto it = sessions_.begin(); it != sessions_.end(); ++it)
      if (it->second < oldest->second)
        oldest = it;
    sessions_.erase(oldest);
  }
  sessions_[id] = now + lifetime_;
  return id;
}

bool LoginSessions::valid(std::string_view id) const {
  if (id.size() != 64)
    return false;
  std::lock_guard lock(mutex_);
  const auto now = Clock::now();
  bool found = false;
  // Compare against every live id so the time does not depend on which one matches.
  for (const auto& [known, expiry] : sessions_)
    found |= constantTimeEqual(id, known) && expiry > now;
  return found;
}

void LoginSessions::revoke(std::string_view id) {
  std::lock_guard lock(mutex_);
  if (auto it = sessions_.find(id); it != sessions_.end())
    sessions_.erase(it);
}

std::optional<std::string_view> cookieValue(std::string_view header, std::string_view name) {
  while (!header.empty()) {
    const std::size_t semi = header.find(';');
    std::string_view pair = header.substr(0, semi);
    while (!pair.empty() && pair.front() == ' ')
      pair.remove_prefix(1);
    const std::size_t eq = pair.find('=');
    if (eq != std::string_view::npos && pair.substr(0, eq) == name)
      return pair.substr(eq + 1);
    if (semi == std::string_view::npos)
      break;
    header.remove_prefix(semi + 1);
  }
  return std::nullopt;
}

}  // namespace garmcap::daemon
