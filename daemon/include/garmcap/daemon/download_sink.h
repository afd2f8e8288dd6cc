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

namespace garmcap::daemon {

/// One chunk of an HTTP/1.1 chunked body: hex size, CRLF, the bytes, CRLF. An empty piece gives
/// "" (a zero-size chunk would end the body; that is the writer's to send, "0\r\n\r\n").
inline std::string httpChunk(const std::string& piece) {
  if (piece.empty())
    return {};
  static const char* kHex = "0123456789abcdef";
  std::string size;
  for (std::size_t n = piece.size(); n; n >>= 4)
    size.insert(size.begin(), kHex[n & 15]);
  return size + "\r\n" + piece + "\r\n";
}

}  // namespace garmcap::daemon
