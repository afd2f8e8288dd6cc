// dsw benchmarks: coordinates (ours vs CGAL 5.5, ns per point×vertex) and grading speed.
// Run: build/bin/dsw_bench  (add --benchmark_filter=... to select). After the Google Benchmark
// table it prints a summary with the CGAL/ours ratios.
#include <benchmark/benchmark.h>

#include <cstdio>

#include "dsw_bench_summary.h"

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv))
    return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  garmcap::dsw::bench::printSummary();
  return 0;
}
