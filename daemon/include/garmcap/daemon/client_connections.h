#pragma once
// Connections per client address. A single address (a misbehaving tablet, a script, one host
// behind which an attacker sits) may hold at most `limit` of the server's connection slots, so
// it cannot take every slot with connections that are busy being served (slow downloads, open
// MJPEG or event streams), which the waiting-for-header eviction cannot free.

#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <utility>

namespace garmcap::daemon {

class ClientConnections {
 public:
  /// One connection counted against its address; released when destroyed.
  class Slot {
   public:
    Slot(ClientConnections& owner, std::string address)
        : owner_(&owner), address_(std::move(address)) {}
    Slot(Slot&& o) noexcept
        : owner_(std::exchange(o.owner_, nullptr)), address_(std::move(o.address_)) {}
    Slot& operator=(Slot&& o) noexcept {
      if (this != &o) {
        if (owner_)
          owner_->release(address_);
        owner_ = std::exchange(o.owner_, nullptr);
        address_ = std::move(o.address_);
      }
      return *this;
    }
    Slot(const Slot&) = delete;
    ~Slot() {
      if (owner_)
        owner_->release(address_);
    }
    const std::string& address() const { return address_; }

   private:
    ClientConnections* owner_;
    std::string address_;
  };

  /// A slot for `address` when it holds fewer than `limit`; `force` counts it regardless (the
  /// caller has just evicted one of that address's connections, which releases its slot later).
  std::optional<Slot> acquire(const std::string& address, int limit, bool force = false) {
    std::lock_guard lock(mutex_);
    int& n = counts_[address];
    if (n >= limit && !force)
      return std::nullopt;
    ++n;
    return std::optional<Slot>(std::in_place, *this, address);
  }

  int count(const std::string& address) const {
    std::lock_guard lock(mutex_);
    const auto it = counts_.find(address);
    return it == counts_.end() ? 0 : it->second;
  }

 private:
  void release(const std::string& address) {
    std::lock_guard lock(mutex_);
    const auto it = counts_.find(address);
    if (it != counts_.end() && --it->second <= 0)
      counts_.erase(it);  // the map holds only addresses with open connections
  }

  mutable std::mutex mutex_;
  std::map<std::string, int> counts_;
};

}  // namespace garmcap::daemon
