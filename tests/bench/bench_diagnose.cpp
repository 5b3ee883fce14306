// Time of `lashid diagnose` (issue 12: at most 2 s per diagnosis of a 15,000-sample recording) and of the joint
// model's normal equations, the part of a fit that every one of a diagnosis' ~1,000 fits pays. How to run it:
// docs/diagnose.md ("Time"); its results: docs/diagnose-history.md ("Time, session by session"); never asserted (the
// machines are shared).
//
// The recordings are the generator's (curved borders), on test seeds whose diagnosis was among the slowest
// measured: colored_noise 9642 (n = 3, m = 6, backlash), the pair input_lag + sensor_drift 9600, and sensor_drift 10669
// (n = 3, m = 6, backlash), the slowest of the held-out seeds 10600-10699.
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <benchmark/benchmark.h>

#include "joint_model_layout.hpp"
#include "joint_model_regression.hpp"
#include "lashid/analysis/joint_model.hpp"
#include "lashid/diagnose/diagnosis.hpp"
#include "lashid/sim/hidden_effect.hpp"

namespace {

using namespace lashid::sim;

HiddenEffectCase curved_case(std::vector<Cause> causes, std::uint64_t seed) {
  HiddenEffectOptions options;
  options.borders = BorderShape::kCurved;
  return generate_hidden_effect_case(causes, seed, options);
}

void BM_Diagnose(benchmark::State& state, std::vector<Cause> causes, std::uint64_t seed) {
  const HiddenEffectCase c = curved_case(causes, seed);
  for (auto _ : state) {
    Diagnosis d = diagnose(c.config, c.recording, "bench");
    benchmark::DoNotOptimize(d);
  }
  state.counters["samples"] = static_cast<double>(flatten(c.recording).size());
}
BENCHMARK_CAPTURE(BM_Diagnose, colored_noise_9642, std::vector<Cause>{Cause::kColoredNoise}, 9642)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);
BENCHMARK_CAPTURE(BM_Diagnose, input_lag_sensor_drift_9600, std::vector<Cause>{Cause::kInputLag, Cause::kSensorDrift},
                  9600)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);
BENCHMARK_CAPTURE(BM_Diagnose, sensor_drift_10669, std::vector<Cause>{Cause::kSensorDrift}, 10669)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);

// The least-squares normal equations of the input-lag model's finer tables (10 segments per interval) on the same
// recording: n = 3, m = 6, about 300 columns, 12,000 identification rows.
void BM_NormalEquations(benchmark::State& state) {
  const HiddenEffectCase c = curved_case({Cause::kColoredNoise}, 9642);
  const FlatRecording data = flatten(c.recording);
  ModelStructure structure;
  structure.op = c.config.op;
  structure.input_lag = 0.3;
  const detail::Layout layout = detail::make_layout(c.config, 10);
  const std::vector<double> w = effective_input(data.v, structure);
  const detail::Basis phi = detail::operator_basis(layout, w, structure.op, nullptr);
  const detail::RegressionShape g = detail::regression_shape(c.config.n, layout.parameters, data, structure);
  for (auto _ : state) {
    detail::NormalEquations ne =
        detail::normal_equations(g, data, structure, phi, detail::lag_groups(data, phi), nullptr);
    benchmark::DoNotOptimize(ne);
  }
  state.counters["columns"] = g.cols;
  state.counters["rows"] = static_cast<double>(g.rows.size());
}
BENCHMARK(BM_NormalEquations)->Unit(benchmark::kMicrosecond);

// A backlash's regimes on the same recording, from a fitted model's borders (one per pass of the regime
// iteration, as many as the fits).
void BM_BacklashRegimes(benchmark::State& state) {
  const HiddenEffectCase c = curved_case({Cause::kColoredNoise}, 9642);
  const FlatRecording data = flatten(c.recording);
  ModelStructure structure;
  structure.op = OperatorKind::kBacklash;
  structure.input_lag = 0.3;
  structure.border_segments = 10;
  const JointModel model = fit_joint_model(c.config, data, structure);
  if (!model.ok) {
    state.SkipWithError(model.failure.c_str());
    return;
  }
  const detail::Layout layout = detail::make_layout(c.config, 10);
  const std::vector<double> w = effective_input(data.v, structure);
  for (auto _ : state) {
    detail::Basis phi = detail::operator_basis(layout, w, structure.op, &model);
    benchmark::DoNotOptimize(phi);
  }
}
BENCHMARK(BM_BacklashRegimes)->Unit(benchmark::kMicrosecond);

}  // namespace

// The heap policy of `lashid` (host_sim/app/main.cpp, keep_freed_heap_pages), so that a diagnosis here costs what
// it costs in the tool: with glibc's defaults the pages of each fit's few MB are returned and faulted in again
// (about 10 % more time on these two recordings).
int main(int argc, char** argv) {
#if defined(__GLIBC__)
  mallopt(M_TOP_PAD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
