#pragma once
// A download written in pieces over a stream route (Router::addStream). StreamSink::write drops
// the oldest unsent chunk for a slow client (right for previews and events, wrong for a file);
// a piece given to writeThen is never dropped, and `drained` runs once it has been written to
// the peer, or as soon as the peer is gone (open() is then false). A writer that produces its
// next piece only from `drained` holds one piece at a time, however large the file. The HTTP
// server's stream sinks implement it (http_session.h); a handler gets it by dynamic_cast.

#include <functional>
#include <string>

namespace garmcap::daemon {

class DownloadSink {
 public:
  virtual ~DownloadSink() = default;
  virtual void writeThen(std::string piece, std::function<void()> drained) = 0;
};

}  // namespace garmcap::daemon
