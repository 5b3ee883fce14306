// Per-sample cost of the least-squares back-ends on the DIS example of the paper (Section 3.5: n = 2, m = 6,
// A = 1 + q^-1 + 0.21 q^-2, B = 70.5 q^-1 - 35.25 q^-2, F^d in closed form, noise variance 16), float and double:
//   grouped/...        GroupedLeastSquares (the project's recursive estimator, sparse row): update, solve, and
//                      "update + one solve per pulse period T = 18" per sample;
//   covariance_rls/... the textbook dense covariance-form RLS (dimension p = n + n m = 14);
//   batch/...          BatchLeastSquares (3.21) in double: accumulation per sample, final solve;
//   identifier/...     SchemeIdentifier::add_pulse_sample (centring + regressor + grouped update) and estimate().
// One step experiment and 1000 pulse periods are simulated once, before any timing; the regressor rows are built
// outside the timed loops (except in identifier/...), and the timed loops cycle through them. Each estimator is
// restarted from its initial state at the end of every pass through the data (once per ~18000 samples), so the
// state always corresponds to a realistic experiment length.
//
// Times are per item: items are samples, except for .../solve and identifier/estimate, where an item is one call.
// The counter fail_frac is the fraction of updates that did not return Status::kOk. An update that fails exits
// early, so its time is not the cost of a real update; after a failure the estimator is restarted from its
// initial state, so that the loop keeps timing real updates. Only covariance_rls/.../float fails (its P loses
// positive definiteness after a few dozen rows in float32, as covariance_rls.hpp warns), at the rate shown.
//
// LASHID_BENCH_ITERATIONS=K fixes every benchmark's iteration count to K (for instruction counting under
// callgrind, see docs/benchmarks.md); without it Google Benchmark chooses the counts as usual.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "../paper_examples.hpp"
#include "lashid/estimator/batch_ls.hpp"
#include "lashid/estimator/covariance_rls.hpp"
#include "lashid/estimator/design.hpp"
#include "lashid/estimator/excitation.hpp"
#include "lashid/estimator/grouped_rls.hpp"
#include "lashid/estimator/identifier.hpp"
#include "lashid/estimator/regressor.hpp"
#include "lashid/estimator/step_mean.hpp"

namespace {

using namespace lashid::est;
using Dis = lashid::test::DisExample;

constexpr int kN = Dis::n;
constexpr int kM = Dis::m;
constexpr int kDim = kN + kN * kM;
constexpr int kPeriod = PulseSchedule<kN, kM>::kPeriod;  // T = n (m + 3) = 18
constexpr int kPeriods = 1000;
constexpr int kStepLength = 1000;
constexpr std::uint64_t kSeed = 0x1a5b1dU;

template <class Scalar>
ExperimentDesign<Scalar, kM> dis_design() {
  ExperimentDesign<Scalar, kM> d;
  d.scheme = Scheme::kDescending;
  d.v_min = static_cast<Scalar>(Dis::v_min);
  d.v_max = static_cast<Scalar>(Dis::v_max);
  for (int j = 0; j < kM; ++j) d.V(j) = static_cast<Scalar>(Dis::V[static_cast<std::size_t>(j)]);
  return d;
}

// v and y of the step experiment (3.4) followed by the pulse experiment (3.1), in double, from the DPE model (3.3):
// u(t) = F^d(v(t)), y(t) = -a1 y(t-1) - a2 y(t-2) + b1 u(t-1) + b2 u(t-2) + xi(t), xi ~ N(0, 16).
struct Recording {
  std::vector<double> step_v, step_y, pulse_v, pulse_y;
};

Recording simulate() {
  const ExcitationGenerator<double, kN, kM> gen(dis_design<double>());
  std::mt19937_64 rng(kSeed);
  std::normal_distribution<double> xi(0.0, std::sqrt(Dis::noise_variance));
  const double u_held = Dis::F_d(Dis::v_max);
  const double y_eq = (Dis::b[0] + Dis::b[1]) * u_held / (1.0 + Dis::a[0] + Dis::a[1]);
  double y1 = y_eq, y2 = y_eq, u1 = u_held, u2 = u_held;  // start at the equilibrium of the held level
  auto plant = [&](double v) {
    const double y = -Dis::a[0] * y1 - Dis::a[1] * y2 + Dis::b[0] * u1 + Dis::b[1] * u2 + xi(rng);
    y2 = y1;
    y1 = y;
    u2 = u1;
    u1 = Dis::F_d(v);
    return y;
  };
  Recording r;
  for (int t = 0; t < kStepLength; ++t) {
    const double v = gen.step_input(t);
    r.step_v.push_back(v);
    r.step_y.push_back(plant(v));
  }
  for (int t = 0; t < kPeriod * kPeriods; ++t) {
    const double v = gen.pulse_input(t);
    r.pulse_v.push_back(v);
    r.pulse_y.push_back(plant(v));
  }
  return r;
}

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "bench_estimator: data set check failed: %s\n", what);
  std::abort();
}

// Everything the timed loops read, in Scalar, built once per type.
template <class Scalar>
struct Dataset {
  using Identifier = SchemeIdentifier<Scalar, kN, kM, GroupedLeastSquares>;
  using Nodes = typename LagrangeBasis<Scalar, kM>::Nodes;

  ExperimentDesign<Scalar, kM> design = dis_design<Scalar>();
  Nodes W = design.W();
  std::vector<Scalar> pulse_v, pulse_y;                      // raw pulse-experiment samples
  std::vector<SparseRegressor<Scalar, kN, kM>> sparse_rows;  // Phi(t), sparse form
  std::vector<Eigen::Matrix<Scalar, kDim, 1>> dense_rows;    // Phi(t), dense form (3.19b)
  std::vector<Scalar> targets;                               // y~(t)
  Identifier after_step;                                     // configured, step experiment done

  Dataset() {
    const Recording rec = simulate();
    if (after_step.configure(design) != Status::kOk) fail("design");
    for (std::size_t t = 0; t < rec.step_v.size(); ++t) {
      if (after_step.add_step_sample(static_cast<Scalar>(rec.step_v[t]), static_cast<Scalar>(rec.step_y[t])) !=
          Status::kOk) {
        fail("step experiment");
      }
    }
    const Scalar held = design.held_level();
    const Scalar ybar0 = after_step.step_mean().mean();
    RegressorBuilder<Scalar, kN, kM> builder(W);
    for (std::size_t t = 0; t < rec.pulse_v.size(); ++t) {
      const Scalar v = static_cast<Scalar>(rec.pulse_v[t]);
      const Scalar y = static_cast<Scalar>(rec.pulse_y[t]);
      pulse_v.push_back(v);
      pulse_y.push_back(y);
      const Scalar v_tilde = v - held;
      const Scalar y_tilde = y - ybar0;
      if (builder.ready()) {
        SparseRegressor<Scalar, kN, kM> row;
        Eigen::Matrix<Scalar, kDim, 1> phi;
        if (builder.sparse(row) != Status::kOk || builder.dense(phi) != Status::kOk) fail("regressor");
        sparse_rows.push_back(row);
        dense_rows.push_back(phi);
        targets.push_back(y_tilde);
      }
      builder.push(v_tilde, y_tilde);
    }
    // The workload must be the real one: the grouped estimate on these rows recovers A within the noise.
    GroupedLeastSquares<Scalar, kN, kM> est(W);
    for (std::size_t r = 0; r < sparse_rows.size(); ++r) {
      if (est.update(sparse_rows[r], targets[r]) != Status::kOk) fail("grouped update");
    }
    const auto sol = est.solve();
    if (sol.status != Status::kOk) fail("grouped solve");
    if (std::fabs(sol.theta(0) - Scalar(1)) > Scalar(0.05) || std::fabs(sol.theta(1) - Scalar(0.21)) > Scalar(0.05)) {
      fail("estimate of A too far from 1 + q^-1 + 0.21 q^-2");
    }
  }
};

template <class Scalar>
const Dataset<Scalar>& dataset() {
  static const Dataset<Scalar> d;
  return d;
}

// Shared tail of the per-sample benchmarks.
void report_samples(benchmark::State& state, std::int64_t failures) {
  state.SetItemsProcessed(state.iterations());
  state.counters["fail_frac"] =
      benchmark::Counter(static_cast<double>(failures), benchmark::Counter::kAvgIterations);
}

// Per-sample update of a recursive back-end on pre-built rows; with SolveEvery > 0, also one solve() every
// SolveEvery samples (the estimate computed on demand once per pulse period).
template <int SolveEvery, class Estimator, class Rows, class Scalar>
void run_updates(benchmark::State& state, const Estimator& fresh, const Rows& rows, const std::vector<Scalar>& targets) {
  Estimator est = fresh;
  Estimator* escape = &est;
  benchmark::DoNotOptimize(escape);  // est is reachable from outside: ClobberMemory() keeps every update
  const std::size_t count = rows.size();
  std::size_t i = 0;
  [[maybe_unused]] int phase = 0;
  std::int64_t failures = 0;
  for (auto _ : state) {
    Status s = est.update(rows[i], targets[i]);
    benchmark::DoNotOptimize(s);
    if (s != Status::kOk) {
      ++failures;
      est = fresh;  // the float covariance form breaks down after a few rows: keep timing real updates
    }
    if constexpr (SolveEvery > 0) {
      if (++phase == SolveEvery) {
        phase = 0;
        auto sol = est.solve();
        benchmark::DoNotOptimize(sol);
      }
    }
    if (++i == count) {
      i = 0;
      est = fresh;
    }
    benchmark::ClobberMemory();
  }
  report_samples(state, failures);
}

// Cost of one solve() on the state after the whole data set.
template <class Estimator, class Rows, class Scalar>
void run_solve(benchmark::State& state, const Estimator& fresh, const Rows& rows, const std::vector<Scalar>& targets) {
  Estimator est = fresh;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (est.update(rows[r], targets[r]) != Status::kOk) {
      state.SkipWithError("update failed");
      return;
    }
  }
  if (est.solve().status != Status::kOk) {
    state.SkipWithError("solve failed");
    return;
  }
  Estimator* escape = &est;
  benchmark::DoNotOptimize(escape);
  for (auto _ : state) {
    auto sol = est.solve();
    benchmark::DoNotOptimize(sol);
    benchmark::ClobberMemory();  // est may have changed: solve() cannot be hoisted out of the loop
  }
  state.SetItemsProcessed(state.iterations());
}

template <class Scalar, int SolveEvery>
void BM_GroupedUpdate(benchmark::State& state) {
  const auto& d = dataset<Scalar>();
  run_updates<SolveEvery>(state, GroupedLeastSquares<Scalar, kN, kM>(d.W), d.sparse_rows, d.targets);
}

template <class Scalar>
void BM_GroupedSolve(benchmark::State& state) {
  const auto& d = dataset<Scalar>();
  run_solve(state, GroupedLeastSquares<Scalar, kN, kM>(d.W), d.sparse_rows, d.targets);
}

template <class Scalar, int SolveEvery>
void BM_CovarianceRlsUpdate(benchmark::State& state) {
  const auto& d = dataset<Scalar>();
  run_updates<SolveEvery>(state, CovarianceRls<Scalar, kN, kM>(d.W), d.dense_rows, d.targets);
}

void BM_BatchUpdate(benchmark::State& state) {
  const auto& d = dataset<double>();
  run_updates<0>(state, BatchLeastSquares<double, kN, kM>(d.W), d.dense_rows, d.targets);
}

void BM_BatchSolve(benchmark::State& state) {
  const auto& d = dataset<double>();
  run_solve(state, BatchLeastSquares<double, kN, kM>(d.W), d.dense_rows, d.targets);
}

// The whole per-sample path of the identifier: centring, off-design checks, sparse regressor, grouped update.
template <class Scalar>
void BM_IdentifierAddPulseSample(benchmark::State& state) {
  const auto& d = dataset<Scalar>();
  auto id = d.after_step;
  auto* escape = &id;
  benchmark::DoNotOptimize(escape);
  const std::size_t count = d.pulse_v.size();
  std::size_t i = 0;
  std::int64_t failures = 0;
  for (auto _ : state) {
    Status s = id.add_pulse_sample(d.pulse_v[i], d.pulse_y[i]);
    benchmark::DoNotOptimize(s);
    if (s != Status::kOk) ++failures;
    if (++i == count) {
      i = 0;
      id = d.after_step;
    }
    benchmark::ClobberMemory();
  }
  report_samples(state, failures);
}

// estimate(): grouped solve + recovery (3.20)-(3.23), after the whole data set.
template <class Scalar>
void BM_IdentifierEstimate(benchmark::State& state) {
  const auto& d = dataset<Scalar>();
  auto id = d.after_step;
  for (std::size_t i = 0; i < d.pulse_v.size(); ++i) {
    if (id.add_pulse_sample(d.pulse_v[i], d.pulse_y[i]) != Status::kOk) {
      state.SkipWithError("add_pulse_sample failed");
      return;
    }
  }
  if (id.estimate().status != Status::kOk) {
    state.SkipWithError("estimate failed");
    return;
  }
  auto* escape = &id;
  benchmark::DoNotOptimize(escape);
  for (auto _ : state) {
    auto e = id.estimate();
    benchmark::DoNotOptimize(e);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations());
}

std::int64_t fixed_iterations() {
  const char* env = std::getenv("LASHID_BENCH_ITERATIONS");
  if (env == nullptr) return 0;
  const long long k = std::strtoll(env, nullptr, 10);
  return k > 0 ? static_cast<std::int64_t>(k) : 0;
}

template <class Fn>
void add(const char* name, Fn&& fn) {
  benchmark::internal::Benchmark* b = benchmark::RegisterBenchmark(name, static_cast<Fn&&>(fn));
  b->Unit(benchmark::kNanosecond);
  if (const std::int64_t k = fixed_iterations(); k > 0) b->Iterations(k);
}

void register_all() {
  add("grouped/update/float", [](benchmark::State& s) { BM_GroupedUpdate<float, 0>(s); });
  add("grouped/update/double", [](benchmark::State& s) { BM_GroupedUpdate<double, 0>(s); });
  add("grouped/solve/float", [](benchmark::State& s) { BM_GroupedSolve<float>(s); });
  add("grouped/solve/double", [](benchmark::State& s) { BM_GroupedSolve<double>(s); });
  add("grouped/update+solve_per_T/float", [](benchmark::State& s) { BM_GroupedUpdate<float, kPeriod>(s); });
  add("grouped/update+solve_per_T/double", [](benchmark::State& s) { BM_GroupedUpdate<double, kPeriod>(s); });
  add("covariance_rls/update/float", [](benchmark::State& s) { BM_CovarianceRlsUpdate<float, 0>(s); });
  add("covariance_rls/update/double", [](benchmark::State& s) { BM_CovarianceRlsUpdate<double, 0>(s); });
  add("covariance_rls/update+solve_per_T/float",
      [](benchmark::State& s) { BM_CovarianceRlsUpdate<float, kPeriod>(s); });
  add("covariance_rls/update+solve_per_T/double",
      [](benchmark::State& s) { BM_CovarianceRlsUpdate<double, kPeriod>(s); });
  add("batch/update/double", [](benchmark::State& s) { BM_BatchUpdate(s); });
  add("batch/solve/double", [](benchmark::State& s) { BM_BatchSolve(s); });
  add("identifier/add_pulse_sample/float", [](benchmark::State& s) { BM_IdentifierAddPulseSample<float>(s); });
  add("identifier/add_pulse_sample/double", [](benchmark::State& s) { BM_IdentifierAddPulseSample<double>(s); });
  add("identifier/estimate/float", [](benchmark::State& s) { BM_IdentifierEstimate<float>(s); });
  add("identifier/estimate/double", [](benchmark::State& s) { BM_IdentifierEstimate<double>(s); });
}

}  // namespace

int main(int argc, char** argv) {
  register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
