// Button to filed item (issue 16): this build's garmcapd against another build (the baseline) in
// one run, alternated, on the same case and machine. Prints per binary the median of each
// capture's request-to-item time and of the steps the daemon logs for it, and their ratio
// (this build / baseline). The machine is shared: read the ratios of one run, not the
// milliseconds across runs.
//
//   capture_latency_bench --baseline OLD/garmcapd --case CASE_DIR [--rounds 3] [--captures 3]
//                         [--button]
// --case: a rig case whose frames the replay camera serves (12 MP: `garmcap rig make --count 1
//   --seed 7 --width 3040 --height 4056 --hard-fraction 0 --out RIG`, then RIG/case_000).
// --rounds: daemon starts per binary; the order alternates (new, old, old, new, ...).
// --captures: dressed captures per start after one bare-form capture; the first of them is
//   reported apart ("first"): it includes what the station prepares per calibration.
// --button: no SKU given, so the hang tag is read (as with the station's button).
// cpu_first, cpu_later: the daemon's CPU time (all threads, user + system) from the request to the
// filed item, which the other sessions' load swells far less than the wall time.
// The steps are the daemon's own job log lines (station_jobs.cpp): the still, its PNG (or
// nothing, for a still stored as delivered) and its store on the camera thread; the bare frame, the
// pipeline (the processor: runCapture, colours, size run; "runCapture" alone from
// pipeline_processor.cpp) and the photos (hang tag, still and photos stored) on the worker.
#include <stdio.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "../e2e/daemon_harness.h"

using namespace garmcap::e2e;
using Clock = std::chrono::steady_clock;

namespace {

// The CPU time (user + system, every thread) the process has used so far, in ms; 0 if unknown.
// A capture's share of it does not swell with other sessions' load as its wall time does (only
// through cache and frequency effects), so it tells what a quiet 2-core station would need.
double cpuMs(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t close = stat.rfind(')');
  if (close == std::string::npos)
    return 0;
  std::istringstream fields(stat.substr(close + 2));
  std::string f;
  double ticks = 0;
  for (int i = 3; i <= 15 && fields >> f; ++i)
    if (i == 14 || i == 15)  // utime, stime
      ticks += std::stod(f);
  return ticks * 1000.0 / static_cast<double>(::sysconf(_SC_CLK_TCK));
}

double median(std::vector<double> v) {
  if (v.empty())
    return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

// One daemon start with the binary GARMCAP_GARMCAPD names: "<step> <ms>" lines on stdout.
int runOnce(const std::string& caseDir, int captures, bool button) {
  TempDir dir;
  DaemonOptions o;
  o.rig = makeSimulatedRig(dir.path(), caseDir);
  o.stderrFile = dir.path() / "garmcapd.log";
  Daemon d(dir.path() / "data", o);
  const auto bare = d.waitJob(d.post("/api/capture/empty").json()["job"].get<std::int64_t>());
  if (bare["state"] != "done") {
    std::fprintf(stderr, "the bare-form capture failed: %s\n", bare.dump().c_str());
    return 1;
  }
  const std::int64_t bareJob = bare["id"].get<std::int64_t>();
  for (int i = 0; i < captures; ++i) {
    const auto t0 = Clock::now();
    const double cpu0 = cpuMs(d.pid());
    const std::string body = button ? "" : R"({"sku": "LAT-)" + std::to_string(i) + R"("})";
    const auto job = d.waitJob(d.post("/api/capture", body).json()["job"].get<std::int64_t>());
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (job["state"] != "done") {
      std::fprintf(stderr, "capture %d failed: %s\n", i, job.dump().c_str());
      return 1;
    }
    std::printf("%s %.1f\n", i == 0 ? "first" : "later", ms);
    std::printf("%s %.1f\n", i == 0 ? "cpu_first" : "cpu_later", cpuMs(d.pid()) - cpu0);
    // The pipeline's own stages, from the item's result.json.
    const Json result =
        d.get("/api/items/" + std::to_string(job["item_id"].get<std::int64_t>()) + "/result.json")
            .json();
    if (result.is_object() && result.contains("timings_ms"))
      for (const auto& [stage, v] : result["timings_ms"].items())
        if (v.is_number() && stage != "total")
          std::printf("stage:%s %.1f\n", stage.c_str(), v.get<double>());
  }
  d.terminate();
  // The job log: each dressed job's steps (the bare-form job's still is left out).
  // "PNG": the still encoded on the camera thread; "as delivered": the camera's own bytes (a
  // replayed rig's file, a V4L2 MJPEG still), nothing encoded (the column stays still_png).
  const std::regex still(
      R"(job (\d+): still (\d+) ms, (?:PNG|as delivered) (\d+) ms, stored (\d+) ms)");
  const std::regex worker(R"(job (\d+): bare frame (\d+) ms, pipeline (\d+) ms, then .* (\d+) ms)");
  const std::regex run(R"(runCapture took (\d+) ms)");
  std::ifstream log(o.stderrFile);
  std::string line;
  std::smatch m;
  while (std::getline(log, line)) {
    if (std::regex_search(line, m, still) && std::stoll(m[1]) != bareJob)
      std::printf("still %s\nstill_png %s\nstill_stored %s\n", m[2].str().c_str(),
                  m[3].str().c_str(), m[4].str().c_str());
    else if (std::regex_search(line, m, worker))
      std::printf("bare_frame %s\npipeline %s\nphotos %s\n", m[2].str().c_str(), m[3].str().c_str(),
                  m[4].str().c_str());
    else if (std::regex_search(line, m, run))
      std::printf("runCapture %s\n", m[1].str().c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string baseline, caseDir;
  int rounds = 3, captures = 3;
  bool button = false, once = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool hasValue = i + 1 < argc;
    if (a == "--baseline" && hasValue)
      baseline = argv[++i];
    else if (a == "--case" && hasValue)
      caseDir = argv[++i];
    else if (a == "--rounds" && hasValue)
      rounds = std::stoi(argv[++i]);
    else if (a == "--captures" && hasValue)
      captures = std::stoi(argv[++i]);
    else if (a == "--button")
      button = true;
    else if (a == "--once")  // internal: one start of the binary GARMCAP_GARMCAPD names
      once = true;
    else {
      std::fprintf(stderr,
                   "usage: %s --baseline GARMCAPD --case CASE_DIR [--rounds N] "
                   "[--captures N] [--button]\n",
                   argv[0]);
      return 2;
    }
  }
  if (caseDir.empty())
    caseDir = (std::filesystem::path(GARMCAP_TEST_DATA_DIR) / "rig" / "case_002").string();
  if (once)
    return runOnce(caseDir, captures, button);
  if (baseline.empty()) {
    std::fprintf(stderr, "--baseline GARMCAPD is required (the build to compare with)\n");
    return 2;
  }
  const std::string self = std::filesystem::canonical("/proc/self/exe").string();
  const std::string current = std::string(GARMCAP_BIN_DIR) + "/garmcapd";
  const std::string names[2] = {"this build", "baseline"};
  const std::string bins[2] = {current, baseline};
  std::map<std::string, std::vector<double>> samples[2];
  for (int r = 0; r < rounds; ++r) {
    for (int k = 0; k < 2; ++k) {
      const int b = (r % 2 == 0) ? k : 1 - k;
      const std::string cmd = "GARMCAP_GARMCAPD='" + bins[b] + "' '" + self + "' --once --case '" +
                              caseDir + "' --captures " + std::to_string(captures) +
                              (button ? " --button" : "");
      FILE* p = popen(cmd.c_str(), "r");
      if (!p)
        return 1;
      char buf[256];
      while (std::fgets(buf, sizeof buf, p)) {
        std::istringstream in(buf);
        std::string step;
        double ms = 0;
        if (in >> step >> ms)
          samples[b][step].push_back(ms);
      }
      if (pclose(p) != 0) {
        std::fprintf(stderr, "%s (%s) failed in round %d\n", names[b].c_str(), bins[b].c_str(), r);
        return 1;
      }
      std::fprintf(stderr, "round %d: %s done\n", r + 1, names[b].c_str());
    }
  }
  std::printf("case %s, %d rounds x %d captures%s\nthis build: %s\nbaseline:   %s\n",
              caseDir.c_str(), rounds, captures, button ? ", hang tag read" : "", current.c_str(),
              baseline.c_str());
  std::printf("%-18s %6s %14s %14s %8s\n", "median ms", "n", "this build", "baseline", "ratio");
  std::vector<std::string> steps = {"first",    "later",      "cpu_first",    "cpu_later",
                                    "still",    "still_png",  "still_stored", "bare_frame",
                                    "pipeline", "runCapture", "photos"};
  for (const auto& [step, v] : samples[1])  // then runCapture's stages (result.json timings_ms)
    if (step.rfind("stage:", 0) == 0)
      steps.push_back(step);
  for (const std::string& step : steps) {
    const auto& a = samples[0][step];
    const auto& b = samples[1][step];
    if (a.empty() && b.empty())
      continue;
    const double ma = median(a), mb = median(b);
    std::printf("%-18s %6zu %14.0f %14.0f %8.2f\n", step.c_str(), a.size(), ma, mb,
                mb > 0 ? ma / mb : 0.0);
  }
  return 0;
}
