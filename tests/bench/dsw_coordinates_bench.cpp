// Mean value coordinates, ours vs CGAL 5.5 Mean_value_coordinates_2 (Simple_cartesian<double>,
// class object reused across queries, as CGAL recommends), on a random concave polygon of n
// vertices with 4096 queries in and around it. Reported as ns per (point × vertex).
#include <CGAL/Barycentric_coordinates_2/Mean_value_coordinates_2.h>
#include <CGAL/Simple_cartesian.h>
#include <benchmark/benchmark.h>

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
  perPointVertex()[impl + "/" + std::to_string(n)] = ns;
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

void cgalRun(benchmark::State& state, BC::Computation_policy_2 policy, const std::string& name) {
  const int n = static_cast<int>(state.range(0));
  const Setup s(n);
  std::vector<CgalPoint> poly;
  for (Eigen::Index i = 0; i < s.cage.rows(); ++i)
    poly.emplace_back(s.cage(i, 0), s.cage(i, 1));
  std::vector<CgalPoint> q;
  for (Eigen::Index k = 0; k < s.queries.rows(); ++k)
    q.emplace_back(s.queries(k, 0), s.queries(k, 1));
  BC::Mean_value_coordinates_2<std::vector<CgalPoint>, Kernel> mvc(poly, policy);
  // The same output as ours: a dense M×N weight matrix.
  Eigen::MatrixXd w(kQueries, n);
  std::vector<double> c;
  c.reserve(static_cast<std::size_t>(n));
  const double t0 = cpuSeconds();
  for (auto _ : state) {
    for (int k = 0; k < kQueries; ++k) {
      c.clear();
      mvc(q[static_cast<std::size_t>(k)], std::back_inserter(c));
      for (int i = 0; i < n; ++i)
        w(k, i) = c[static_cast<std::size_t>(i)];
    }
    benchmark::DoNotOptimize(w.data());
  }
  record(state, name, cpuSeconds() - t0, n);
}

void BM_MvcCgalFastWithEdgeCases(benchmark::State& state) {
  cgalRun(state, BC::Computation_policy_2::FAST_WITH_EDGE_CASES, "cgal_fast");
}
void BM_MvcCgalPreciseWithEdgeCases(benchmark::State& state) {
  cgalRun(state, BC::Computation_policy_2::PRECISE_WITH_EDGE_CASES, "cgal_precise");
}

BENCHMARK(BM_MvcOurs)->Arg(8)->Arg(16)->Arg(32)->Arg(64);
BENCHMARK(BM_MvcCgalFastWithEdgeCases)->Arg(8)->Arg(16)->Arg(32)->Arg(64);
BENCHMARK(BM_MvcCgalPreciseWithEdgeCases)->Arg(8)->Arg(16)->Arg(32)->Arg(64);

}  // namespace
}  // namespace garmcap::dsw::bench
