#pragma once
// The harness of the end-to-end tests: the real garmcapd as a child process on a free 127.0.0.1
// port with --simulated, a blocking HTTP client, and the replay rigs it captures from. Shared by
// the e2e test sources (tests/e2e/*_test.cpp); every wait is bounded. Also read-only looks into
// the daemon's data folder (catalog, image store).
#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "../daemon/test_util.h"

namespace garmcap::e2e {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using namespace std::chrono_literals;
using Json = nlohmann::json;

// GARMCAP_GARMCAPD runs another build (a benchmark compares two binaries in one run).
inline const std::string kBin = std::getenv("GARMCAP_GARMCAPD")
                                    ? std::string(std::getenv("GARMCAP_GARMCAPD"))
                                    : std::string(GARMCAP_BIN_DIR) + "/garmcapd";

using garmcap::daemon::test::TempDir;

struct Reply {
  int status = 0;
  std::string body;
  std::string contentType;
  std::string disposition;  // Content-Disposition
  Json json() const { return Json::parse(body, nullptr, false); }
};

/// A request with the given header fields as they are (Host included), for the attacks a
/// browser or a hostile client makes. A HEAD's answer is read without a body.
/// A raw TCP connection to the daemon's loopback port (-1 on failure); `from`: the client's own
/// address (any of 127.0.0.0/8 is this machine's loopback), so that one test can be many clients.
inline int connectTo(int port, const char* from = nullptr) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (from) {
    sockaddr_in src{};
    src.sin_family = AF_INET;
    inet_pton(AF_INET, from, &src.sin_addr);
    if (bind(fd, reinterpret_cast<sockaddr*>(&src), sizeof src) != 0) {
      close(fd);
      return -1;
    }
  }
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    close(fd);
    return -1;
  }
  return fd;
}

/// The client address this thread's requests come from ("": the default, 127.0.0.1). Any of
/// 127.0.0.0/8 reaches the loopback port, so one test can be many clients (tablets) at once.
inline thread_local std::string clientAddress;

inline Reply httpCallWith(int port, http::verb verb, const std::string& target,
                          const std::vector<std::pair<std::string, std::string>>& fields,
                          const std::string& body = "") {
  asio::io_context io;
  beast::tcp_stream stream(io);
  stream.expires_after(30s);
  if (!clientAddress.empty()) {
    stream.socket().open(asio::ip::tcp::v4());
    stream.socket().bind(asio::ip::tcp::endpoint(asio::ip::make_address(clientAddress), 0));
  }
  stream.connect(asio::ip::tcp::endpoint(asio::ip::make_address("127.0.0.1"),
                                         static_cast<unsigned short>(port)));
  http::request<http::string_body> req{verb, target, 11};
  for (const auto& [k, v] : fields)
    req.set(k, v);
  req.body() = body;
  req.prepare_payload();
  beast::error_code ec;
  http::write(stream, req, ec);
  beast::flat_buffer buf;
  http::response_parser<http::string_body> parser;
  parser.body_limit(256u << 20);
  if (verb == http::verb::head)
    parser.skip(true);
  http::read(stream, buf, parser, ec);
  if (ec)
    return {0, ec.message(), "", ""};
  auto res = parser.release();
  return {static_cast<int>(res.result_int()), res.body(),
          std::string(res[http::field::content_type]),
          std::string(res[http::field::content_disposition])};
}

inline Reply httpCall(int port, http::verb verb, const std::string& target,
                      const std::string& body = "", const std::string& token = "") {
  std::vector<std::pair<std::string, std::string>> fields = {{"Host", "127.0.0.1"}};
  if (!token.empty())
    fields.emplace_back("Authorization", "Bearer " + token);
  if (!body.empty())
    fields.emplace_back("Content-Type", "application/json");
  return httpCallWith(port, verb, target, fields, body);
}

// rig.json of a rig whose one case is the folder c1 (the format capture::readRig reads).
inline void writeOneCaseRigJson(const std::filesystem::path& rig, const std::string& type) {
  std::ofstream(rig / "rig.json")
      << R"({"format": "garmcap-rig", "version": 1, "cases": [{"id": "c1", "dir": "c1", "type": ")"
      << type << R"(", "attributes": {}, "hard": false}]})";
}

// A one-case replay rig (green screen, grey form, a red garment) in the test's temp tree, so the
// e2e tests do not depend on the scene simulator being wired to the synthetic camera.
inline std::filesystem::path makeRig(const std::filesystem::path& root) {
  const auto rig = root / "rig";
  std::filesystem::create_directories(rig / "c1");
  cv::Mat empty(480, 640, CV_8UC3, cv::Scalar(40, 180, 40));
  cv::ellipse(empty, {320, 240}, {70, 200}, 0, 0, 360, cv::Scalar(170, 170, 170), cv::FILLED);
  cv::Mat dressed = empty.clone();
  cv::rectangle(dressed, {250, 200}, {390, 380}, cv::Scalar(30, 30, 200), cv::FILLED);
  cv::imwrite((rig / "c1" / "empty.png").string(), empty);
  cv::imwrite((rig / "c1" / "dressed.png").string(), dressed);
  std::ofstream(rig / "c1" / "truth.json") << R"({"type": "skirt", "measurements": {}})";
  writeOneCaseRigJson(rig, "skirt");
  return rig;
}

// A one-case replay rig holding a case of the bundled simulator rig (a real form on a green
// screen, with its dressed frame): the station calibrates on it and GarmCap measures it.
inline std::filesystem::path makeSimulatedRig(
    const std::filesystem::path& root,
    const std::filesystem::path& src = std::filesystem::path(GARMCAP_TEST_DATA_DIR) / "rig" /
                                       "case_002") {
  const auto rig = root / "simrig";
  std::filesystem::create_directories(rig / "c1");
  // The frames as the case holds them, PNG or JPEG (docs/formats.md).
  for (const char* f : {"empty.png", "empty.jpg", "dressed.png", "dressed.jpg", "truth.json"}) {
    if (std::filesystem::exists(src / f))
      std::filesystem::copy_file(src / f, rig / "c1" / f);
  }
  writeOneCaseRigJson(rig, "skirt");
  return rig;
}

/// How to start the daemon beyond the defaults (--simulated on a replay rig, loopback port 0).
struct DaemonOptions {
  std::vector<std::string> args;  // extra command-line arguments
  std::filesystem::path rig;      // replay rig folder; empty: a fake one-case rig in the data dir
  std::vector<std::pair<std::string, std::string>> env;  // e.g. NOTIFY_SOCKET, WATCHDOG_USEC
  std::filesystem::path stderrFile;  // the daemon's log; empty: /dev/null (or the test's stderr
                                     // with GARMCAP_E2E_VERBOSE)
  // The kernel's memory-deny-write-execute (prctl PR_SET_MDWE, Linux >= 6.3), what the unit's
  // MemoryDenyWriteExecute=yes asks of systemd; the daemon fails to start if it cannot be set.
  bool denyWriteExecute = false;
  bool synthetic = false;  // the simulated station's own camera (scenes rendered on demand)
};

#ifndef PR_SET_MDWE  // Debian 12's kernel headers (6.1) predate it
#define PR_SET_MDWE 65
#define PR_GET_MDWE 66
#define PR_MDWE_REFUSE_EXEC_GAIN 1
#endif

/// Sets memory-deny-write-execute on the calling process (irreversible): true when in force.
inline bool denyWriteExecute() {
  return prctl(PR_SET_MDWE, PR_MDWE_REFUSE_EXEC_GAIN, 0, 0, 0) == 0 &&
         prctl(PR_GET_MDWE, 0, 0, 0, 0) == PR_MDWE_REFUSE_EXEC_GAIN;
}

// The daemon as a child process; its port is read from its first stdout line.
class Daemon {
 public:
  explicit Daemon(const std::filesystem::path& data, std::vector<std::string> extra = {},
                  std::filesystem::path rigDir = {})
      : Daemon(data, DaemonOptions{std::move(extra), std::move(rigDir), {}, {}}) {}
  Daemon(const std::filesystem::path& data, const DaemonOptions& o) {
    const auto rig = o.synthetic ? std::filesystem::path() : o.rig.empty() ? makeRig(data) : o.rig;
    int out[2];
    if (pipe(out) != 0)
      throw std::runtime_error("pipe");
    pid_ = fork();
    if (pid_ == 0) {
      dup2(out[1], 1);
      close(out[0]);
      close(out[1]);
      if (!o.stderrFile.empty()) {
        const int log = open(o.stderrFile.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
        dup2(log, 2);
      } else if (!getenv("GARMCAP_E2E_VERBOSE")) {
        dup2(open("/dev/null", O_WRONLY), 2);
      }
      // Only what the test asks for reaches the daemon's systemd integration.
      for (const char* v : {"NOTIFY_SOCKET", "WATCHDOG_USEC", "WATCHDOG_PID"})
        unsetenv(v);
      for (const auto& [k, v] : o.env)
        setenv(k.c_str(), v.c_str(), 1);
      if (o.denyWriteExecute && !denyWriteExecute())
        _exit(126);
      std::vector<std::string> args = {kBin,          "--simulated", "--data",
                                       data.string(), "--listen",    "127.0.0.1:0"};
      if (!o.synthetic)
        args.insert(args.end(), {"--camera", "replay", "--device", rig.string()});
      args.insert(args.end(), o.args.begin(), o.args.end());
      std::vector<char*> argv;
      for (auto& a : args)
        argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(kBin.c_str(), argv.data());
      _exit(127);
    }
    close(out[1]);
    // Read "garmcapd listening on 127.0.0.1:PORT" (bounded wait).
    const std::string kPrefix = "garmcapd listening on ";
    std::string line;
    const auto deadline = std::chrono::steady_clock::now() + 60s;
    fcntl(out[0], F_SETFL, O_NONBLOCK);
    auto complete = [&] {
      const auto at = line.find(kPrefix);
      return at != std::string::npos && line.find('\n', at) != std::string::npos;
    };
    while (std::chrono::steady_clock::now() < deadline && !complete()) {
      char c[256];
      const ssize_t n = read(out[0], c, sizeof c);
      if (n > 0)
        line.append(c, static_cast<std::size_t>(n));
      else if (n == 0)
        break;
      else
        std::this_thread::sleep_for(10ms);
    }
    close(out[0]);
    if (!complete())
      throw std::runtime_error("garmcapd did not start: '" + line + "'");
    line = line.substr(line.find(kPrefix));
    line = line.substr(0, line.find('\n'));
    const auto colon = line.rfind(':');
    port_ = std::stoi(line.substr(colon + 1));
  }
  ~Daemon() {
    if (pid_ > 0)
      kill9();
  }
  int port() const { return port_; }
  pid_t pid() const { return pid_; }
  void kill9() {
    ::kill(pid_, SIGKILL);
    int st = 0;
    waitpid(pid_, &st, 0);
    pid_ = -1;
  }
  void signal(int sig) const { ::kill(pid_, sig); }
  /// SIGTERM and wait (bounded); returns the exit status or -1 on timeout.
  int terminate(std::chrono::seconds limit = 90s) {
    ::kill(pid_, SIGTERM);
    return wait(limit);
  }
  /// Waits for the exit (bounded); the exit status, 128 + signal, or -1 on timeout.
  int wait(std::chrono::seconds limit) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < deadline) {
      int st = 0;
      if (waitpid(pid_, &st, WNOHANG) == pid_) {
        pid_ = -1;
        return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
      }
      std::this_thread::sleep_for(20ms);
    }
    return -1;
  }
  Reply get(const std::string& t) const { return httpCall(port_, http::verb::get, t); }
  Reply post(const std::string& t, const std::string& body = "") const {
    return httpCall(port_, http::verb::post, t, body);
  }
  Json waitJob(std::int64_t id, std::chrono::seconds limit = 180s) const {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    Json j;
    while (std::chrono::steady_clock::now() < deadline) {
      j = get("/api/jobs/" + std::to_string(id)).json();
      if (j.value("state", "") == "done" || j.value("state", "") == "failed")
        return j;
      std::this_thread::sleep_for(50ms);
    }
    return j;
  }

 private:
  pid_t pid_ = -1;
  int port_ = 0;
};

inline std::string integrity(const std::filesystem::path& db) {
  sqlite3* h = nullptr;
  sqlite3_open_v2(db.c_str(), &h, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* s = nullptr;
  sqlite3_prepare_v2(h, "PRAGMA integrity_check", -1, &s, nullptr);
  std::string out = sqlite3_step(s) == SQLITE_ROW
                        ? reinterpret_cast<const char*>(sqlite3_column_text(s, 0))
                        : "no answer";
  sqlite3_finalize(s);
  sqlite3_close(h);
  return out;
}

inline std::vector<std::string> column(const std::filesystem::path& db, const char* sql) {
  sqlite3* h = nullptr;
  sqlite3_open_v2(db.c_str(), &h, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* s = nullptr;
  std::vector<std::string> out;
  if (sqlite3_prepare_v2(h, sql, -1, &s, nullptr) == SQLITE_OK)
    while (sqlite3_step(s) == SQLITE_ROW)
      out.emplace_back(sqlite3_column_text(s, 0)
                           ? reinterpret_cast<const char*>(sqlite3_column_text(s, 0))
                           : "");
  sqlite3_finalize(s);
  sqlite3_close(h);
  return out;
}

inline std::set<std::string> blobsOnDisk(const std::filesystem::path& data) {
  std::set<std::string> out;
  std::error_code ec;
  for (auto& e : std::filesystem::recursive_directory_iterator(data / "blobs", ec))
    if (e.is_regular_file() && e.path().parent_path().filename() != "tmp")
      out.insert(e.path().filename().string());
  return out;
}

}  // namespace garmcap::e2e
