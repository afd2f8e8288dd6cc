// Grading speed (seed §4.6: "less than one millisecond" for the whole dress on a 2012 desktop).
// The source dress of tests/data/designs graded (a) to one size: encoding, target draft,
// decoding; (b) to a 9-size run: encoding once, 9 target drafts and decodings; and the parts.
// CPU time of this thread, in ms per operation, is printed in the summary.
#include <benchmark/benchmark.h>

#include <ctime>
#include <string>
#include <vector>

#include "dsw_bench_summary.h"
#include "garmcap/drafts/measurements.h"
#include "garmcap/drafts/pattern_io.h"
#include "garmcap/dsw/grading.h"

namespace garmcap::dsw::bench {
namespace {

double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

const drafts::Pattern& source() {
  static const drafts::Pattern p =
      drafts::readPatternJson(std::string(GARMCAP_TEST_DATA_DIR) + "/designs/dress_55.json");
  return p;
}

drafts::Measurements body(const std::string& size) {
  return drafts::readMeasurementsJson(std::string(GARMCAP_TEST_DATA_DIR) + "/bodies/table4_2_" +
                                      size + ".json");
}

// Nine bodies from size 55 scaled by 0.88 ... 1.12 (every measurement), a 9-size run.
std::vector<drafts::Measurements> nineBodies() {
  std::vector<drafts::Measurements> out;
  const drafts::Measurements b = body("55");
  for (int i = 0; i < 9; ++i)
    out.push_back(b.scaled(0.88 + 0.03 * i));
  return out;
}

void finish(benchmark::State& state, const std::string& name, double t0) {
  millis()[name] = (threadCpuSeconds() - t0) * 1e3 / static_cast<double>(state.iterations());
}

void BM_GradeDressOneSize(benchmark::State& state) {
  const drafts::Measurements target = body("77");
  const double t0 = threadCpuSeconds();
  for (auto _ : state) {
    auto g = gradePattern(source(), target);
    if (!g)
      state.SkipWithError(g.error().message.c_str());
    benchmark::DoNotOptimize(g);
  }
  finish(state, "grade dress to one size (encode + target draft + decode)", t0);
}

void BM_GradeDressNineSizes(benchmark::State& state) {
  const auto bodies = nineBodies();
  const double t0 = threadCpuSeconds();
  for (auto _ : state) {
    auto enc = encodePattern(source(), source().regions, CoordMethod::kMeanValue);
    for (const auto& b : bodies) {
      auto draft = targetDraft(source(), b);
      auto g = decodePattern(*enc, *draft);
      benchmark::DoNotOptimize(g);
    }
  }
  finish(state, "grade dress to 9 sizes (encode once, 9 target drafts + decodes)", t0);
}

void BM_EncodeDress(benchmark::State& state) {
  const double t0 = threadCpuSeconds();
  for (auto _ : state) {
    auto enc = encodePattern(source(), source().regions, CoordMethod::kMeanValue);
    benchmark::DoNotOptimize(enc);
  }
  finish(state, "part: encode every panel point of the dress", t0);
}

void BM_TargetDraft(benchmark::State& state) {
  const drafts::Measurements target = body("77");
  const double t0 = threadCpuSeconds();
  for (auto _ : state) {
    auto d = targetDraft(source(), target);
    benchmark::DoNotOptimize(d);
  }
  finish(state, "part: target draft (drafts recipe)", t0);
}

void BM_DecodeDress(benchmark::State& state) {
  auto enc = encodePattern(source(), source().regions, CoordMethod::kMeanValue);
  auto draft = targetDraft(source(), body("77"));
  const double t0 = threadCpuSeconds();
  for (auto _ : state) {
    auto g = decodePattern(*enc, *draft);
    benchmark::DoNotOptimize(g);
  }
  finish(state, "part: decode (matrix products)", t0);
}

BENCHMARK(BM_GradeDressOneSize)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_GradeDressNineSizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_EncodeDress)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_TargetDraft)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DecodeDress)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace garmcap::dsw::bench
