// Latency of the real garmcapd under the load of a shop's clients (issue 16): N clients on
// loopback ask for the status, a page of the catalog, an item's photo and its pattern, while two
// more watch the MJPEG preview; first with the station idle, then while it files captures one
// after another. Prints p50 / p99 per kind of request in both phases, the preview's frame rate,
// and each capture's time from the request to its item, against the same captures with no
// clients. The two phases run in one process, so their ratio is what to read, not the
// absolute times (a loaded machine moves both).
//
//   daemon_load_bench [--clients 50] [--captures 5] [--seconds-idle 8] [--case CASE_DIR]
// --case: the rig case whose frames the station replays (default: the bundled rig's case_002,
// 864x1152; a 12 MP one: `garmcap rig make --count 1 --seed 7 --width 3000 --height 4000`).
// The first capture after the bare form is timed on its own: it includes what the station
// prepares per calibration.
//   GARMCAP_GARMCAPD=/path/to/other/garmcapd daemon_load_bench ...   (another build)
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <map>
#include <mutex>

#include "../e2e/daemon_harness.h"

using namespace garmcap::e2e;
using Clock = std::chrono::steady_clock;

namespace {

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

struct Samples {
  std::mutex m;
  std::map<std::string, std::vector<double>> ms;
  std::map<std::string, int> failed;
  void add(const std::string& kind, double v, bool ok) {
    std::lock_guard lock(m);
    ms[kind].push_back(v);
    if (!ok)
      ++failed[kind];
  }
};

double percentile(std::vector<double> v, double p) {
  if (v.empty())
    return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * static_cast<double>(v.size())))];
}

// Frames of /stream.mjpg read until `stop`, counted by their part headers.
int watchPreview(int port, const std::atomic<bool>& stop) {
  const int fd = connectTo(port);
  if (fd < 0)
    return -1;
  const std::string req = "GET /stream.mjpg HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
  send(fd, req.data(), req.size(), MSG_NOSIGNAL);
  timeval tv{0, 200000};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  int frames = 0;
  std::string tail;
  char buf[65536];
  const std::string marker = "Content-Type: image/jpeg";
  while (!stop) {
    const ssize_t n = recv(fd, buf, sizeof buf, 0);
    if (n == 0)
      break;
    if (n < 0)
      continue;
    tail.append(buf, static_cast<std::size_t>(n));
    for (std::size_t at = tail.find(marker); at != std::string::npos; at = tail.find(marker))
      ++frames, tail.erase(0, at + marker.size());
    if (tail.size() > marker.size())
      tail.erase(0, tail.size() - marker.size());
  }
  close(fd);
  return frames;
}

struct Phase {
  std::map<std::string, std::pair<double, double>> p50p99;
  std::map<std::string, std::size_t> count;
  std::map<std::string, int> failed;
  double previewFps = 0;
  std::vector<double> captureMs;
  int capturesFailed = 0;
};

// `clients` clients (0: none) for the whole phase; `captures` captures one after another, or
// none and `idleSeconds` of load.
Phase runPhase(const Daemon& d, int clients, int captures, double idleSeconds,
               const std::vector<std::string>& urls) {
  Samples s;
  std::atomic<bool> stop{false};
  std::vector<std::thread> threads;
  for (int c = 0; c < clients; ++c)
    threads.emplace_back([&, c] {
      clientAddress = "127.0.1." + std::to_string(c % 250 + 1);  // one address per tablet
      for (std::size_t i = static_cast<std::size_t>(c); !stop; ++i) {
        const std::string& url = urls[i % urls.size()];
        const auto t0 = Clock::now();
        const auto r = d.get(url);
        const std::string kind = url.find("/images/") != std::string::npos  ? "image"
                                 : url.find("pattern") != std::string::npos ? "pattern.svg"
                                 : url.find("/api/items") == 0              ? "items"
                                                                            : "status";
        s.add(kind, msSince(t0), r.status == 200);
        if (r.status != 200 && std::getenv("GARMCAP_BENCH_VERBOSE"))
          std::fprintf(stderr, "%s: %d %s\n", url.c_str(), r.status, r.body.substr(0, 80).c_str());
      }
    });
  std::vector<int> frames(clients > 0 ? 2 : 0);
  std::vector<std::thread> watchers;
  for (std::size_t w = 0; w < frames.size(); ++w)
    watchers.emplace_back([&, w] { frames[w] = watchPreview(d.port(), stop); });
  const auto t0 = Clock::now();
  Phase out;
  if (captures == 0) {
    std::this_thread::sleep_for(std::chrono::duration<double>(idleSeconds));
  } else {
    for (int k = 0; k < captures; ++k) {
      const auto c0 = Clock::now();
      const auto job = d.post("/api/capture", R"({"sku": "LOAD-)" + std::to_string(k) + "\"}");
      const auto done = d.waitJob(job.json()["job"].get<std::int64_t>());
      out.captureMs.push_back(msSince(c0));
      if (done["state"] != "done")
        ++out.capturesFailed;
    }
  }
  const double seconds = msSince(t0) / 1000;
  stop = true;
  for (auto& t : threads)
    t.join();
  for (auto& t : watchers)
    t.join();
  for (auto& [kind, v] : s.ms) {
    out.p50p99[kind] = {percentile(v, 0.5), percentile(v, 0.99)};
    out.count[kind] = v.size();
  }
  out.failed = s.failed;
  int allFrames = 0;
  for (int f : frames)
    allFrames += std::max(f, 0);
  out.previewFps = frames.empty() ? 0 : allFrames / seconds / static_cast<double>(frames.size());
  return out;
}

void print(const char* name, const Phase& p) {
  std::printf("%s\n", name);
  for (const auto& [kind, q] : p.p50p99)
    std::printf("  %-12s n %6zu  p50 %7.1f ms  p99 %7.1f ms  failed %d\n", kind.c_str(),
                p.count.at(kind), q.first, q.second, p.failed.count(kind) ? p.failed.at(kind) : 0);
  if (p.previewFps > 0)
    std::printf("  preview      %.2f frames/s per viewer\n", p.previewFps);
  if (!p.captureMs.empty()) {
    double sum = 0;
    for (double v : p.captureMs)
      sum += v;
    std::printf("  captures     %zu, mean %.0f ms, max %.0f ms, failed %d\n", p.captureMs.size(),
                sum / static_cast<double>(p.captureMs.size()),
                *std::max_element(p.captureMs.begin(), p.captureMs.end()), p.capturesFailed);
    // Each one as well: runs of different builds are compared by their medians.
    std::printf("  capture ms  ");
    for (double v : p.captureMs)
      std::printf(" %.0f", v);
    std::printf("\n");
  }
}

}  // namespace

int main(int argc, char** argv) {
  int clients = 50, captures = 5;
  double idleSeconds = 8;
  std::string caseDir;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--clients")
      clients = std::stoi(argv[i + 1]);
    else if (a == "--captures")
      captures = std::stoi(argv[i + 1]);
    else if (a == "--seconds-idle")
      idleSeconds = std::stod(argv[i + 1]);
    else if (a == "--case")
      caseDir = argv[i + 1];
    else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  TempDir dir;
  Daemon d(dir.path() / "data", {},
           caseDir.empty() ? makeSimulatedRig(dir.path()) : makeSimulatedRig(dir.path(), caseDir));
  if (d.waitJob(d.post("/api/capture/empty").json()["job"].get<std::int64_t>())["state"] !=
      "done") {
    std::fprintf(stderr, "the bare-form capture failed\n");
    return 1;
  }
  const auto f0 = Clock::now();
  const auto first = d.waitJob(d.post("/api/capture", R"({"sku": "LOAD-SEED"})").json()["job"]);
  const double firstMs = msSince(f0);
  if (first["state"] != "done") {
    std::fprintf(stderr, "the first capture failed: %s\n", first.dump().c_str());
    return 1;
  }
  const std::string item = "/api/items/" + std::to_string(first["item_id"].get<std::int64_t>());
  const Json shown = d.get(item).json();
  std::vector<std::string> urls = {"/api/status", "/api/items?limit=10", item + "/pattern.svg"};
  for (const auto& [kind, im] : shown["images"].items())
    if (kind == "product" || kind == "cutout")
      urls.push_back(im["url"].get<std::string>());
  std::printf("garmcapd %s, %d clients, %d captures, urls:", kBin.c_str(), clients, captures);
  for (const auto& u : urls)
    std::printf(" %s", u.c_str());
  std::printf("\nfirst capture after the bare form: %.0f ms (request to item)\n", firstMs);
  const Phase alone = runPhase(d, 0, captures, 0, urls);
  const Phase idle = runPhase(d, clients, 0, idleSeconds, urls);
  const Phase busy = runPhase(d, clients, captures, 0, urls);
  print("captures alone (no clients)", alone);
  print("clients, station idle", idle);
  print("clients during captures", busy);
  if (!alone.captureMs.empty() && !busy.captureMs.empty()) {
    double a = 0, b = 0;
    for (double v : alone.captureMs)
      a += v;
    for (double v : busy.captureMs)
      b += v;
    std::printf("capture time under load / alone: %.2f\n", b / a);
  }
  for (const auto& [kind, q] : busy.p50p99)
    if (idle.p50p99.count(kind))
      std::printf("%s p99 during captures / idle: %.2f\n", kind.c_str(),
                  q.second / std::max(idle.p50p99.at(kind).second, 0.01));
  const int bad = busy.capturesFailed + alone.capturesFailed;
  d.terminate();
  return bad ? 1 : 0;
}
