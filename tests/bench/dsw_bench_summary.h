#pragma once
// Results the dsw benchmarks record for the summary printed after the run.
#include <cstdio>
#include <map>
#include <string>

namespace garmcap::dsw::bench {

/// ns per (point × vertex) keyed by "<impl>/<n vertices>".
inline std::map<std::string, double>& perPointVertex() {
  static std::map<std::string, double> results;
  return results;
}

/// CGAL/ours time ratios keyed by "fast/<n>", "precise/<n>" (medians over interleaved rounds)
/// and "fast_min/<n>" (the worst round).
inline std::map<std::string, double>& ratios() {
  static std::map<std::string, double> results;
  return results;
}

/// Milliseconds per operation keyed by a name ("grade dress to one size", ...).
inline std::map<std::string, double>& millis() {
  static std::map<std::string, double> results;
  return results;
}

inline void printSummary() {
  auto& r = perPointVertex();
  if (!r.empty()) {
    auto& q = ratios();
    std::printf(
        "\nns per (point x vertex)   n   ours   cgal_fast_edge  cgal_precise_edge  ratio_fast  "
        "ratio_precise  worst_round_fast\n");
    for (const int n : {8, 16, 32, 64}) {
      const std::string k = "/" + std::to_string(n);
      if (!r.count("ours" + k))
        continue;
      const double ours = r["ours" + k];
      const double fast = r.count("cgal_fast" + k) ? r["cgal_fast" + k] : 0;
      const double precise = r.count("cgal_precise" + k) ? r["cgal_precise" + k] : 0;
      // Interleaved medians when BM_MvcRatio ran, else the separate benchmarks' ratio.
      const double rf = q.count("fast" + k) ? q["fast" + k] : fast / ours;
      const double rp = q.count("precise" + k) ? q["precise" + k] : precise / ours;
      const double worst = q.count("fast_min" + k) ? q["fast_min" + k] : rf;
      std::printf(
          "                        %3d  %6.2f   %8.2f        %8.2f           %5.1fx      %5.1fx"
          "         %5.1fx\n",
          n, ours, fast, precise, rf, rp, worst);
    }
  }
  for (const auto& [name, ms] : millis())
    std::printf("%s: %.4f ms\n", name.c_str(), ms);
}

}  // namespace garmcap::dsw::bench
