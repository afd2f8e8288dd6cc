#pragma once
// A throwaway PostgreSQL server for the hub's tests: initdb and pg_ctl in a temp folder, on a
// free 127.0.0.1 port, its socket in that folder too, trust auth for the one test user. initdb
// refuses to run as root, so as root the server runs as `nobody` (runuser) in a folder chowned
// to it. Stopped (immediate) and removed at destruction. Every wait is bounded.
#include <grp.h>
#include <netinet/in.h>
#include <pwd.h>
#include <sys/socket.h>
#include <sys/types.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>

namespace garmcap::hub::test {

/// The folder of initdb/pg_ctl (Debian: /usr/lib/postgresql/<major>/bin), or nullopt.
inline std::optional<std::filesystem::path> postgresBinDir() {
  namespace fs = std::filesystem;
  if (const char* env = std::getenv("GARMCAP_PG_BIN"); env && fs::exists(fs::path(env) / "initdb"))
    return fs::path(env);
  std::error_code ec;
  std::optional<fs::path> best;
  for (const auto& d : fs::directory_iterator("/usr/lib/postgresql", ec)) {
    const auto bin = d.path() / "bin";
    if (fs::exists(bin / "initdb") && fs::exists(bin / "pg_ctl") && (!best || bin > *best))
      best = bin;
  }
  return best;
}

/// A free TCP port on 127.0.0.1 (bound to 0 and released: a race only with other programs).
inline int freeLoopbackPort() {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = 0;
  socklen_t len = sizeof a;
  if (s < 0 || ::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
      ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &len) != 0) {
    if (s >= 0)
      ::close(s);
    throw std::runtime_error("no free loopback port");
  }
  ::close(s);
  return ntohs(a.sin_port);
}

class TempPostgres {
 public:
  TempPostgres() {
    namespace fs = std::filesystem;
    auto bin = postgresBinDir();
    if (!bin)
      throw std::runtime_error("no PostgreSQL server binaries (apt install postgresql-15)");
    bin_ = *bin;
    std::random_device rd;
    asRoot_ = ::geteuid() == 0;
    // As root the server runs as nobody, who must reach the folder: /tmp, not a $TMPDIR that
    // may be private to root.
    dir_ = (asRoot_ ? fs::path("/tmp") : fs::temp_directory_path()) /
           ("garmcap-pg-" + std::to_string(::getpid()) + "-" + std::to_string(rd()));
    fs::create_directories(dir_);
    if (asRoot_) {
      const passwd* pw = ::getpwnam("nobody");
      if (!pw)
        throw std::runtime_error("running as root and there is no user 'nobody' for PostgreSQL");
      if (::chown(dir_.c_str(), pw->pw_uid, pw->pw_gid) != 0)
        throw std::runtime_error("cannot chown " + dir_.string() + " to nobody");
    }
    port_ = freeLoopbackPort();
    run(q(bin_ / "initdb") + " -D " + q(dir_ / "data") +
            " -U garmcap --auth=trust -E UTF8 --no-locale --no-sync >" + q(dir_ / "initdb.log") +
            " 2>&1",
        "initdb");
    start();
  }
  ~TempPostgres() {
    stop();
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  TempPostgres(const TempPostgres&) = delete;
  TempPostgres& operator=(const TempPostgres&) = delete;

  /// Starts the server (again) on the same port and data; waits until it accepts connections.
  void start() {
    // fsync off: a test server's data may be lost in a power cut, not in a crash of the
    // server (a commit still reaches the WAL before it is acknowledged).
    const std::string opts = "-p " + std::to_string(port_) + " -k " + dir_.string() +
                             " -c listen_addresses=127.0.0.1 -c fsync=off "
                             "-c full_page_writes=off";
    run(q(bin_ / "pg_ctl") + " -D " + q(dir_ / "data") + " -l " + q(dir_ / "server.log") + " -o '" +
            opts + "' -w -t 60 start >/dev/null 2>&1",
        "pg_ctl start");
    running_ = true;
  }
  /// Stops it at once (like a crash: the next start recovers from the WAL).
  void stop() {
    if (!running_)
      return;
    run(q(bin_ / "pg_ctl") + " -D " + q(dir_ / "data") +
            " -m immediate -w -t 60 stop "
            ">/dev/null 2>&1",
        "pg_ctl stop", false);
    running_ = false;
  }

  int port() const { return port_; }
  /// A libpq connection string for `database` (over TCP on loopback).
  std::string url(const std::string& database = "postgres") const {
    return "host=127.0.0.1 port=" + std::to_string(port_) + " user=garmcap dbname=" + database +
           " connect_timeout=10";
  }
  /// Creates a database (names chosen by the test: [a-z0-9_]).
  void createDatabase(const std::string& name) const {
    run(q(bin_ / "psql") + " -X -q -v ON_ERROR_STOP=1 -h 127.0.0.1 -p " + std::to_string(port_) +
            " -U garmcap -d postgres -c 'CREATE DATABASE " + name + "' >/dev/null 2>&1",
        "CREATE DATABASE " + name);
  }
  /// Runs SQL through psql (the server's own client: an independent reader of the database).
  std::string psql(const std::string& database, const std::string& sql) const {
    // Own files per call: tests call this from more than one thread.
    const std::string n = std::to_string(counter_++);
    const auto out = dir_ / ("psql-" + n + ".out");
    const auto in = dir_ / ("psql-" + n + ".sql");
    std::ofstream(in) << sql;
    run(q(bin_ / "psql") + " -X -q -A -t -v ON_ERROR_STOP=1 -h 127.0.0.1 -p " +
            std::to_string(port_) + " -U garmcap -d " + database + " -f " + q(in) + " >" + q(out) +
            " 2>&1",
        "psql");
    std::ifstream f(out);
    std::stringstream s;
    s << f.rdbuf();
    std::string text = s.str();
    while (!text.empty() && text.back() == '\n')
      text.pop_back();
    return text;
  }
  std::string log() const {
    std::ifstream f(dir_ / "server.log");
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
  }

 private:
  static std::string q(const std::filesystem::path& p) { return "'" + p.string() + "'"; }
  void run(const std::string& command, const std::string& what, bool check = true) const {
    // As root, the server's programs run as nobody (initdb and postgres refuse root).
    const std::string cmd = asRoot_ ? "runuser -u nobody -- sh -c " + shellQuote(command) : command;
    const int rc = std::system(cmd.c_str());
    if (check && rc != 0)
      throw std::runtime_error(what + " failed (exit " + std::to_string(rc) + "): " + command);
  }
  static std::string shellQuote(const std::string& s) {
    std::string out = "'";
    for (char c : s)
      out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
  }

  std::filesystem::path bin_, dir_;
  int port_ = 0;
  bool asRoot_ = false;
  bool running_ = false;
  mutable std::atomic<int> counter_{0};
};

}  // namespace garmcap::hub::test
