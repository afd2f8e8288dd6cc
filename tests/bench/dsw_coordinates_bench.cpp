// Mean value coordinates, ours vs CGAL 5.5 Mean_value_coordinates_2 (Simple_cartesian<double>,
// class object reused across queries, as CGAL recommends), on a random concave polygon of n
// vertices with 4096 queries in and around it. Reported as ns per (point × vertex); the
// summary's ratios are medians over interleaved rounds (BM_MvcRatio).
#include <CGAL/Barycentric_coordinates_2/Mean_value_coordinates_2.h>
#include <CGAL/Simple_cartesian.h>
#include <benchmark/benchmark.h>

#include <algorithm>
#include <ctime>
#include <random>
#include <vector>

#include "../dsw/test_polygons.h"
#include "dsw_bench_summary.h"
#include "garmcap/dsw/mean_value_coordinates.h"

namespace garmcap::dsw::bench {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using CgalPoint = Kernel::Point_2;
namespace BC = CGAL::Barycentric_coordinates;
constexpr int kQueries = 4096;

struct Setup {
  Points cage;
  Points queries;
  explicit Setup(int n) {
    std::mt19937 rng(static_cast<unsigned>(n));
    cage = testing::randomStar(n, rng);
    queries = testing::randomPointsAround(cage, kQueries, rng, 0.25);
  }
};

// Thread CPU time: the build machine is shared, so wall time would count other jobs.
double cpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

void record(benchmark::State& state, const std::string& impl, double seconds, int n) {
  const double pv = static_cast<double>(state.iterations()) * kQueries * n;
  const double ns = seconds * 1e9 / pv;
  state.counters["ns_per_point_vertex"] = ns;
  // The summary's figures come from BM_MvcRatio's interleaved rounds when it ran.
  perPointVertex().emplace(impl + "/" + std::to_string(n), ns);
}

void BM_MvcOurs(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const Setup s(n);
  Eigen::MatrixXd w;
  const double t0 = cpuSeconds();
  for (auto _ : state) {
    auto problem = meanValueCoordinatesUnchecked(s.cage, s.queries, w);
    benchmark::DoNotOptimize(problem);
    benchmark::DoNotOptimize(w.data());
  }
  record(state, "ours", cpuSeconds() - t0, n);
}

// CGAL's copies of a Setup's cage and queries.
struct CgalInput {
  std::vector<CgalPoint> poly, queries;
  explicit CgalInput(const Setup& s) {
    for (Eigen::Index i = 0; i < s.cage.rows(); ++i)
      poly.emplace_back(s.cage(i, 0), s.cage(i, 1));
    for (Eigen::Index k = 0; k < s.queries.rows(); ++k)
      queries.emplace_back(s.queries(k, 0), s.queries(k, 1));
  }
};

// One CGAL pass over all queries into the same output as ours: a dense M×N weight matrix.
template <class Mvc>
void cgalPass(Mvc& mvc, const std::vector<CgalPoint>& q, int n, Eigen::MatrixXd& w,
              std::vector<double>& c) {
  for (int k = 0; k < kQueries; ++k) {
    c.clear();
    mvc(q[static_cast<std::size_t>(k)], std::back_inserter(c));
    for (int i = 0; i < n; ++i)
      w(k, i) = c[static_cast<std::size_t>(i)];
  }
  benchmark::DoNotOptimize(w.data());
}

void cgalRun(benchmark::State& state, BC::Computation_policy_2 policy, const std::string& name) {
  const int n = static_cast<int>(state.range(0));
  const Setup s(n);
  const CgalInput in(s);
  BC::Mean_value_coordinates_2<std::vector<CgalPoint>, Kernel> mvc(in.poly, policy);
  Eigen::MatrixXd w(kQueries, n);
  std::vector<double> c;
  c.reserve(static_cast<std::size_t>(n));
  const double t0 = cpuSeconds();
  for (auto _ : state)
    cgalPass(mvc, in.queries, n, w, c);
  record(state, name, cpuSeconds() - t0, n);
}

void BM_MvcCgalFastWithEdgeCases(benchmark::State& state) {
  cgalRun(state, BC::Computation_policy_2::FAST_WITH_EDGE_CASES, "cgal_fast");
}
void BM_MvcCgalPreciseWithEdgeCases(benchmark::State& state) {
  cgalRun(state, BC::Computation_policy_2::PRECISE_WITH_EDGE_CASES, "cgal_precise");
}

// The ratio, measured so that it survives a loaded machine: 9 rounds, each timing ours and
// CGAL's two policies back to back on the same polygon and queries (thread CPU time, at least
// 20 ms each), and the median per implementation and of the per-round ratios. A slow spell
// then hits both sides of a round alike instead of one benchmark of the table.
template <class F>
double nsPerPointVertex(F&& run, int n) {
  int reps = 0;
  const double t0 = cpuSeconds();
  double t = t0;
  while (t - t0 < 0.02) {
    run();
    ++reps;
    t = cpuSeconds();
  }
  return (t - t0) * 1e9 / (static_cast<double>(reps) * kQueries * n);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void BM_MvcRatio(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const Setup s(n);
  const CgalInput in(s);
  BC::Mean_value_coordinates_2<std::vector<CgalPoint>, Kernel> fast(
      in.poly, BC::Computation_policy_2::FAST_WITH_EDGE_CASES);
  BC::Mean_value_coordinates_2<std::vector<CgalPoint>, Kernel> precise(
      in.poly, BC::Computation_policy_2::PRECISE_WITH_EDGE_CASES);
  Eigen::MatrixXd w(kQueries, n);
  std::vector<double> c;
  c.reserve(static_cast<std::size_t>(n));
  auto ours = [&] {
    auto problem = meanValueCoordinatesUnchecked(s.cage, s.queries, w);
    benchmark::DoNotOptimize(problem);
    benchmark::DoNotOptimize(w.data());
  };
  std::vector<double> o, f, p, rf, rp;
  for (auto _ : state) {
    for (int round = 0; round < 9; ++round) {
      o.push_back(nsPerPointVertex(ours, n));
      f.push_back(nsPerPointVertex([&] { cgalPass(fast, in.queries, n, w, c); }, n));
      p.push_back(nsPerPointVertex([&] { cgalPass(precise, in.queries, n, w, c); }, n));
      rf.push_back(f.back() / o.back());
      rp.push_back(p.back() / o.back());
    }
  }
  const std::string k = "/" + std::to_string(n);
  perPointVertex()["ours" + k] = median(o);
  perPointVertex()["cgal_fast" + k] = median(f);
  perPointVertex()["cgal_precise" + k] = median(p);
  ratios()["fast" + k] = median(rf);
  ratios()["precise" + k] = median(rp);
  ratios()["fast_min" + k] = *std::min_element(rf.begin(), rf.end());
  state.counters["ratio_fast"] = median(rf);
  state.counters["ratio_precise"] = median(rp);
}

BENCHMARK(BM_MvcRatio)
    ->Arg(8)
    ->Arg(16)
    ->Arg(32)
    ->Arg(64)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MvcOurs)->Arg(8)->Arg(16)->Arg(32)->Arg(64);
BENCHMARK(BM_MvcCgalFastWithEdgeCases)->Arg(8)->Arg(16)->Arg(32)->Arg(64);
BENCHMARK(BM_MvcCgalPreciseWithEdgeCases)->Arg(8)->Arg(16)->Arg(32)->Arg(64);

}  // namespace
}  // namespace garmcap::dsw::bench
