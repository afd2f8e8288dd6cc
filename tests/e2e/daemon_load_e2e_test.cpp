// Issue 16: slow clients on the shop's network must not starve a normal one, and a long download
// to a slow reader is not cut by the request timeout.

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <atomic>

#include "daemon_harness.h"

namespace garmcap::e2e {
namespace {

bool sendAll(int fd, const std::string& s) {
  return send(fd, s.data(), s.size(), MSG_NOSIGNAL | MSG_DONTWAIT) ==
         static_cast<ssize_t>(s.size());
}

// 300 clients that connect, start a request and then trickle header lines (reconnecting when
// the station drops them), while one normal client asks for the status twenty times.
TEST(DaemonLoad, ThreeHundredSlowClientsDoNotStarveANormalOne) {
  TempDir dir;
  Daemon d(dir.path());
  std::atomic<bool> stop{false};
  std::atomic<int> reconnects{0};
  std::thread attacker([&] {
    std::vector<int> fds;
    for (int i = 0; i < 300; ++i) {
      const int fd = connectTo(d.port());
      if (fd >= 0 && sendAll(fd, "GET /api/status HTTP/1.1\r\nHost: 127.0.0.1\r\n"))
        fds.push_back(fd);
    }
    while (!stop) {
      for (int& fd : fds) {
        if (fd >= 0 && sendAll(fd, "X-Slow: 1\r\n"))
          continue;
        if (fd >= 0)
          close(fd);
        fd = connectTo(d.port());
        if (fd >= 0)
          sendAll(fd, "GET /api/status HTTP/1.1\r\nHost: 127.0.0.1\r\n");
        ++reconnects;
      }
      std::this_thread::sleep_for(200ms);
    }
    for (int fd : fds)
      if (fd >= 0)
        close(fd);
  });
  std::this_thread::sleep_for(1500ms);  // every slot taken
  std::vector<double> ms;
  for (int i = 0; i < 20; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    auto r = d.get("/api/status");
    ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    EXPECT_EQ(r.status, 200) << "request " << i << ": " << r.body;
    std::this_thread::sleep_for(100ms);
  }
  stop = true;
  attacker.join();
  std::sort(ms.begin(), ms.end());
  std::printf("normal client beside 300 slow ones: median %.1f ms, max %.1f ms, %d reconnects\n",
              ms[ms.size() / 2], ms.back(), reconnects.load());
  EXPECT_LT(ms.back(), 1000.0);
  EXPECT_EQ(d.terminate(), 0);
}

// One address holding connections that are all busy being served (event streams: nothing to
// evict) takes at most max_connections_per_client slots; other clients still get in. Without the
// per-client limit the 60 streams fill all 40 slots and the normal client gets 503.
TEST(DaemonLoad, OneClientsOpenStreamsCannotTakeEverySlot) {
  TempDir dir;
  const auto conf = dir.path() / "garmcapd.toml";
  std::ofstream(conf) << "[http]\nmax_connections = 40\nmax_connections_per_client = 12\n";
  Daemon d(dir.path() / "data", {"--config", conf.string()});
  std::vector<int> streams;
  int refused = 0, open = 0;
  for (int i = 0; i < 60; ++i) {
    const int fd = connectTo(d.port(), "127.0.0.2");
    ASSERT_GE(fd, 0) << "cannot connect from 127.0.0.2";
    sendAll(fd, "GET /api/events HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
    timeval tv{2, 0};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    char buf[512];
    const ssize_t n = recv(fd, buf, sizeof buf - 1, 0);
    const std::string head = n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : "";
    if (head.rfind("HTTP/1.1 200", 0) == 0) {
      ++open;
    } else {
      EXPECT_NE(head.find("503"), std::string::npos) << head;
      EXPECT_NE(head.find("too many connections from this client"), std::string::npos) << head;
      ++refused;
    }
    streams.push_back(fd);
  }
  EXPECT_EQ(open, 12);
  EXPECT_EQ(refused, 48);
  for (int i = 0; i < 10; ++i) {
    auto r = d.get("/api/status");
    EXPECT_EQ(r.status, 200) << "request " << i << ": " << r.body;
  }
  for (int fd : streams)
    close(fd);
  // Closed streams give their slots back: the same address is served again.
  std::this_thread::sleep_for(300ms);
  const int fd = connectTo(d.port(), "127.0.0.2");
  ASSERT_GE(fd, 0);
  sendAll(fd, "GET /api/status HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n");
  timeval tv{2, 0};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  char buf[64];
  const ssize_t n = recv(fd, buf, sizeof buf - 1, 0);
  close(fd);
  EXPECT_EQ(std::string(buf, n > 12 ? 12 : 0), "HTTP/1.1 200");
  EXPECT_EQ(d.terminate(), 0);
}

// A client that connects and sends nothing is closed after header_timeout_s.
TEST(DaemonLoad, SilentConnectionIsClosedAfterTheHeaderTimeout) {
  TempDir dir;
  const auto conf = dir.path() / "garmcapd.toml";
  std::ofstream(conf) << "[http]\nheader_timeout_s = 1\n";
  Daemon d(dir.path() / "data", {"--config", conf.string()});
  const int fd = connectTo(d.port());
  ASSERT_GE(fd, 0);
  timeval tv{4, 0};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  const auto t0 = std::chrono::steady_clock::now();
  char c;
  const ssize_t n = recv(fd, &c, 1, 0);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  close(fd);
  EXPECT_EQ(n, 0) << "the station should close the silent connection";
  EXPECT_GT(s, 0.8);
  EXPECT_LT(s, 3.0);
  EXPECT_EQ(d.get("/api/status").status, 200);
  EXPECT_EQ(d.terminate(), 0);
}

}  // namespace
}  // namespace garmcap::e2e
