// On-target cost of the estimator (n = 2, m = 6, float) on the Cortex-M cores of QEMU's mps2 boards, run by the test
// lashid_bench_estimator_runs_in_qemu. See docs/on-target-cost.md for the method and the numbers.
//
// The image generates the paper's DIS example (Section 3.5) on target, before any timing: the step experiment
// (L = 2000) and 128 pulse periods (T = 18, 2304 samples) of A = 1 + q^-1 + 0.21 q^-2, B = 70.5 q^-1 - 35.25 q^-2,
// F^d in closed form, plus deterministic pseudo-noise of standard deviation 4 (variance 16, as in the paper). Then it
// counts guest instructions with SysTick under QEMU -icount shift=0 (1 SysTick cycle = 40 instructions) for
//   (a) SchemeIdentifier<float,2,6>::add_pulse_sample, per sample (centring, checks, sparse regressor, grouped RLS)
//   (b) estimate(false) once per pulse period, per call and amortised per sample
//   (c) (a) + (b) per sample, timed as one loop: the figure for the 300-instruction goal
//   (d) estimate(true), per call (the final estimate, with standard errors)
//   (e) the textbook CovarianceRls<float,2,6>::update on pre-built dense rows, per update
// and prints `cost <name> <value>` lines on the semihosting console. Exit code 0 when the estimates are sane (the
// timed code did real work), 1 otherwise; the 300-instruction goal is reported, not asserted.
#include <bit>
#include <cstdint>

#include "lashid/estimator/covariance_rls.hpp"
#include "lashid/estimator/excitation.hpp"
#include "lashid/estimator/identifier.hpp"
#include "lashid/estimator/regressor.hpp"
#include "lashid/firmware/run_design.hpp"
#include "lashid/hal/mps2.hpp"
#include "paper_dis_example.hpp"

namespace est = lashid::est;
namespace mps2 = lashid::hal::mps2;
using Clock = mps2::SysTickClock;
// The paper's DIS example (paper_dis_example.hpp).
using lashid::bench::border_d, lashid::bench::Plant, lashid::bench::kVMin, lashid::bench::kVMax;
using lashid::bench::kA1, lashid::bench::kA2, lashid::bench::kB1, lashid::bench::kB2;

namespace {

constexpr int N = 2;
constexpr int M = 6;
// The grouped estimator as the generic firmware image compiles it: capacity n <= 4, m <= 10 (run_design.hpp),
// configured at run time for n = 2, m = 6. The textbook form is dense, compiled for exactly n = 2, m = 6.
constexpr int kCapacityN = lashid::fw::kMaxOrder;
constexpr int kCapacityM = lashid::fw::kMaxPoints;
using Identifier = est::SchemeIdentifier<float, kCapacityN, kCapacityM>;
using Estimate = Identifier::Estimate;
using Textbook = est::CovarianceRls<float, N, M>;
using Builder = est::RegressorBuilder<float, kCapacityN, kCapacityM>;
using TextbookBuilder = est::RegressorBuilder<float, N, M>;
using Grouped = est::GroupedLeastSquares<float, kCapacityN, kCapacityM>;
using SparseRow = est::SparseRegressor<float, kCapacityN, kCapacityM>;

constexpr int kPeriod = est::PulseSchedule<N, M>::kPeriod;  // T = n (m + 3) = 18
constexpr int kPeriods = 128;  // every group's 64-row block is merged at least twice: the amortised cost includes it
constexpr int kSamples = kPeriod * kPeriods;
constexpr int kStepLength = 2000;
constexpr int kOverheadRegions = 4096;  // empty regions averaged for the overhead
constexpr float kInstrPerCycle = static_cast<float>(mps2::kInstructionsPerCycleIcount0);
constexpr int kGoal = 300;

est::ExperimentDesign<float, kCapacityM> dis_design() {
  est::ExperimentDesign<float, kCapacityM> d;
  d.scheme = est::Scheme::kDescending;
  d.m = M;
  d.v_min = kVMin;
  d.v_max = kVMax;
  d.V.head<M>() << -3.0f, -2.0f, -1.0f, 1.0f, 2.0f, 3.0f;
  return d;
}

// The pulse experiment's samples, and an identifier that has seen the step experiment (the state every timed pass
// starts from). Sparse rows and centred targets for the bare-update breakdown.
float g_v[kSamples];
float g_y[kSamples];
Identifier g_after_step;
SparseRow g_rows[kSamples];
float g_targets[kSamples];
int g_row_count = 0;

bool generate() {
  const auto design = dis_design();
  if (g_after_step.configure(design, N) != est::Status::kOk) return false;
  const est::ExcitationGenerator<float, kCapacityN, kCapacityM> gen(design, N);
  Plant plant(border_d(design.held_level()));
  bool ok = true;
  for (int t = 0; t <= kStepLength; ++t) {
    // From t = 1 on the backlash sits at the held output (3.4)-(3.5); at t = 0 the input is the opposite bound.
    ok = ok && g_after_step.add_step_sample(gen.step_input(t), plant.next(border_d(design.held_level()))) ==
                   est::Status::kOk;
  }
  Builder builder(design.W(), N, M);
  const float mean = g_after_step.step_mean().mean();
  for (int t = 0; t < kSamples; ++t) {
    g_v[t] = gen.pulse_input(t);
    g_y[t] = plant.next(border_d(g_v[t]));
    const float y_tilde = g_y[t] - mean;
    if (builder.ready()) {
      ok = ok && builder.sparse(g_rows[g_row_count]) == est::Status::kOk;
      g_targets[g_row_count++] = y_tilde;
    }
    builder.push(g_v[t] - design.held_level(), y_tilde);
  }
  return ok;
}

// ---- The timed code (noinline: one place each in the disassembly) --------------------------------------------------

// Forces `value` to exist in memory: the compiler may not drop or sink the computation of a result nobody reads.
template <class T>
void escape(const T& value) {
  __asm__ volatile("" : : "r"(&value) : "memory");
}

// (a): every sample through the identifier; returns how many did not return kOk (all do on this data).
[[gnu::noinline]] int feed(Identifier& id, const float* v, const float* y, int count) {
  int not_ok = 0;
  for (int t = 0; t < count; ++t) not_ok += id.add_pulse_sample(v[t], y[t]) != est::Status::kOk ? 1 : 0;
  return not_ok;
}

// (c): the same, plus estimate_into(false) after every kPeriod-th sample, as the firmware does (into one estimate
// kept across periods).
Estimate g_latest;
[[gnu::noinline]] int feed_and_estimate(Identifier& id, const float* v, const float* y, int count, int& bad_estimates) {
  int not_ok = 0;
  int phase = 0;
  for (int t = 0; t < count; ++t) {
    not_ok += id.add_pulse_sample(v[t], y[t]) != est::Status::kOk ? 1 : 0;
    if (++phase == kPeriod) {
      phase = 0;
      id.estimate_into(g_latest, /*with_std_errors=*/false);
      escape(g_latest);
      bad_estimates += g_latest.status != est::Status::kOk ? 1 : 0;
    }
  }
  return not_ok;
}

[[gnu::noinline]] void estimate_into(const Identifier& id, bool with_std_errors, Estimate& out) {
  id.estimate_into(out, with_std_errors);
  escape(out);
}

// Breakdown of (a): the grouped update alone, on pre-built sparse rows.
[[gnu::noinline]] int bare_grouped(Grouped& ls, const SparseRow* rows, const float* targets, int count) {
  int not_ok = 0;
  for (int r = 0; r < count; ++r) not_ok += ls.update(rows[r], targets[r]) != est::Status::kOk ? 1 : 0;
  return not_ok;
}

// The dense row (3.19b) the textbook form needs (Lagrange polynomials evaluated), not part of (e).
[[gnu::noinline]] est::Status dense_row(const TextbookBuilder& builder, Textbook::Vector& phi) { return builder.dense(phi); }

// (e): one textbook update.
[[gnu::noinline]] est::Status textbook_update(Textbook& rls, const Textbook::Vector& phi, float y_tilde) {
  return rls.update(phi, y_tilde);
}

// ---- Measurement helpers -------------------------------------------------------------------------------------------

// Instructions of an empty timed region (two back-to-back cycles() reads), averaged: subtracted from every region.
float empty_region_instructions() {
  std::uint32_t sum = 0;
  for (int i = 0; i < kOverheadRegions; ++i) {
    const std::uint32_t t0 = Clock::cycles();
    __asm__ volatile("" ::: "memory");
    const std::uint32_t t1 = Clock::cycles();
    sum += t1 - t0;
  }
  return static_cast<float>(sum) * kInstrPerCycle / static_cast<float>(kOverheadRegions);
}

// Instructions per item of `regions` timed regions that took `cycles` in total over `items` items.
float per_item(std::uint32_t cycles, int regions, int items, float overhead) {
  return (static_cast<float>(cycles) * kInstrPerCycle - static_cast<float>(regions) * overhead) /
         static_cast<float>(items);
}

void line(const char* name, float value, int decimals = 1) {
  mps2::Text<120> t;
  t << "cost " << name << ' ';
  t.fixed(value, decimals) << '\n';
  mps2::semihosting::write(t.c_str());
}

void line(const char* name, std::uint32_t value) {
  mps2::Text<120> t;
  t << "cost " << name << ' ' << value << '\n';
  mps2::semihosting::write(t.c_str());
}

int g_failures = 0;
void check(bool ok, const char* what) {
  if (ok) return;
  ++g_failures;
  mps2::Text<160> t;
  t << "FAIL: " << what << '\n';
  mps2::semihosting::write(t.c_str());
}

float abs_diff(float a, float b) { return a > b ? a - b : b - a; }

// Working copies (static: the identifier and the textbook P are a few KiB, kept off the stack).
Identifier g_id;
Identifier g_id2;
Grouped g_grouped;
Textbook g_textbook;
Estimate g_estimate;

}  // namespace

int main() {
  {
    mps2::Text<200> t;
    t << "lashid bench_estimator: " << mps2::core_name() << " on " << mps2::machine_name() << "; DIS example, n = "
      << static_cast<std::uint32_t>(N) << ", m = " << static_cast<std::uint32_t>(M) << ", float, "
      << static_cast<std::uint32_t>(kPeriods) << " pulse periods of " << static_cast<std::uint32_t>(kPeriod)
      << " = " << static_cast<std::uint32_t>(kSamples) << " samples\n";
    mps2::semihosting::write(t.c_str());
  }
  check(generate(), "data generation (design, step experiment or regressor rows)");
  Clock::start();
  const float overhead = empty_region_instructions();
  line("empty_region_instr", overhead);

  // (a) add_pulse_sample, the whole experiment as one timed region.
  g_id = g_after_step;
  std::uint32_t t0 = Clock::cycles();
  const int feed_not_ok = feed(g_id, g_v, g_y, kSamples);
  std::uint32_t t1 = Clock::cycles();
  const float update = per_item(t1 - t0, 1, kSamples, overhead);
  check(feed_not_ok == 0, "add_pulse_sample returned a non-ok status");

  // (c) the same plus estimate(false) once per period, as one timed region.
  g_id2 = g_after_step;
  int bad_periodic = 0;
  t0 = Clock::cycles();
  const int feed2_not_ok = feed_and_estimate(g_id2, g_v, g_y, kSamples, bad_periodic);
  t1 = Clock::cycles();
  const float total = per_item(t1 - t0, 1, kSamples, overhead);
  check(feed2_not_ok == 0, "add_pulse_sample (with estimates) returned a non-ok status");

  // (b) estimate(false) and (d) estimate(true) at the end of every period, each call its own region (the updates in
  // between are not timed). The cost depends a little on the state (which groups have a merged total and a partial
  // block), so both are averaged over the same 128 states the firmware sees; the maximum is the worst single call.
  g_id2 = g_after_step;
  std::uint32_t periodic_cycles = 0;
  std::uint32_t periodic_max = 0;
  std::uint32_t full_cycles = 0;
  std::uint32_t full_max = 0;
  for (int p = 0; p < kPeriods; ++p) {
    (void)feed(g_id2, g_v + p * kPeriod, g_y + p * kPeriod, kPeriod);
    t0 = Clock::cycles();
    estimate_into(g_id2, false, g_estimate);
    t1 = Clock::cycles();
    periodic_cycles += t1 - t0;
    periodic_max = t1 - t0 > periodic_max ? t1 - t0 : periodic_max;
    t0 = Clock::cycles();
    estimate_into(g_id2, true, g_estimate);
    t1 = Clock::cycles();
    full_cycles += t1 - t0;
    full_max = t1 - t0 > full_max ? t1 - t0 : full_max;
  }
  const float periodic = per_item(periodic_cycles, kPeriods, kPeriods, overhead);
  const float full = per_item(full_cycles, kPeriods, kPeriods, overhead);

  // Breakdown of (a): the bare grouped update on pre-built sparse rows.
  (void)g_grouped.reset(dis_design().W(), N, M);
  t0 = Clock::cycles();
  const int bare_not_ok = bare_grouped(g_grouped, g_rows, g_targets, g_row_count);
  t1 = Clock::cycles();
  const float bare = per_item(t1 - t0, 1, g_row_count, overhead);
  check(bare_not_ok == 0, "GroupedLeastSquares::update returned a non-ok status");

  // (e) the textbook covariance form on the dense rows (3.19b), one region per update; the rows are built and,
  // after a failure (P no longer positive definite: 1 + phi'P phi <= 0), P is re-initialised outside the regions.
  const Eigen::Matrix<float, M, 1> W = dis_design().W().head<M>();
  g_textbook = Textbook(W);
  TextbookBuilder builder(W);
  const float mean = g_after_step.step_mean().mean();
  std::uint32_t dense_cycles = 0;
  std::uint32_t ok_cycles = 0;
  std::uint32_t failed_cycles = 0;
  std::uint32_t ok_updates = 0;
  std::uint32_t failed_updates = 0;
  for (int t = 0; t < kSamples; ++t) {
    const float y_tilde = g_y[t] - mean;
    if (builder.ready()) {
      Textbook::Vector phi;
      t0 = Clock::cycles();
      const est::Status built = dense_row(builder, phi);
      t1 = Clock::cycles();
      dense_cycles += t1 - t0;
      check(built == est::Status::kOk, "dense regressor");
      t0 = Clock::cycles();
      const est::Status s = textbook_update(g_textbook, phi, y_tilde);
      t1 = Clock::cycles();
      if (s == est::Status::kOk) {
        ok_cycles += t1 - t0;
        ++ok_updates;
      } else {
        failed_cycles += t1 - t0;
        ++failed_updates;
        (void)g_textbook.reset(W);
      }
    }
    builder.push(g_v[t] - kVMax, y_tilde);
  }
  const float textbook = per_item(ok_cycles, static_cast<int>(ok_updates), static_cast<int>(ok_updates), overhead);
  const float dense = per_item(dense_cycles, kSamples - N, kSamples - N, overhead);
  const float textbook_failed =
      failed_updates == 0U
          ? 0.0f
          : per_item(failed_cycles, static_cast<int>(failed_updates), static_cast<int>(failed_updates), overhead);

  const float amortised_estimate = periodic / static_cast<float>(kPeriod);
  line("grouped_update_instr_per_sample", update);                         // (a)
  line("grouped_bare_update_instr_per_row", bare);                         // breakdown of (a)
  line("estimate_periodic_instr_per_call", periodic);                      // (b)
  line("estimate_periodic_instr_per_sample", amortised_estimate);          // (b) / T
  line("estimate_periodic_max_instr_per_call", static_cast<float>(periodic_max) * kInstrPerCycle - overhead);
  line("grouped_total_instr_per_sample", total);                           // (c), timed as one loop
  line("grouped_total_sum_instr_per_sample", update + amortised_estimate);  // (a) + (b) / T, cross-check of (c)
  line("estimate_with_std_errors_instr_per_call", full);                   // (d)
  line("estimate_with_std_errors_max_instr_per_call", static_cast<float>(full_max) * kInstrPerCycle - overhead);
  line("textbook_update_instr_per_sample", textbook);                      // (e), successful updates
  line("textbook_failed_update_instr_per_call", textbook_failed);
  line("textbook_dense_row_instr_per_sample", dense);
  line("textbook_updates_ok", ok_updates);
  line("textbook_updates_failed", failed_updates);
  line("periodic_estimates_not_ok", static_cast<std::uint32_t>(bad_periodic));
  line("textbook_over_grouped_total", textbook / total, 2);
  {
    mps2::Text<120> t;
    t << "cost goal_" << static_cast<std::uint32_t>(kGoal) << "_instr_per_sample "
      << (total <= static_cast<float>(kGoal) ? "met" : "missed") << '\n';
    mps2::semihosting::write(t.c_str());
  }

  // The timed code did real work: the final estimate is that of the DIS example (se(a) ~ 0.005 here).
  estimate_into(g_id, true, g_estimate);
  check(g_estimate.status == est::Status::kOk, "final estimate status");
  check(abs_diff(g_estimate.a(0), kA1) < 0.05f && abs_diff(g_estimate.a(1), kA2) < 0.05f, "estimate of A");
  check(abs_diff(g_estimate.b(0), kB1) < 3.0f && abs_diff(g_estimate.b(1), kB2) < 3.0f, "estimate of B");
  check(bad_periodic <= 1, "periodic estimates (only the first period may be not yet excited)");
  {
    // A fingerprint of the final estimate's bits (Theta and its standard errors): equal before and after a change of
    // the estimator's code means the change did not alter a single rounding on this core.
    std::uint32_t bits = 0;
    for (int k = 0; k < N + N * M; ++k) {  // Theta of n = 2, m = 6 (the capacity's other entries are zero)
      bits = bits * 31U + std::bit_cast<std::uint32_t>(g_estimate.ls.theta(k));
      bits = bits * 31U + std::bit_cast<std::uint32_t>(g_estimate.ls.std_error(k));
    }
    mps2::Text<80> t;
    t << "cost estimate_bits ";
    t.hex(bits) << '\n';
    mps2::semihosting::write(t.c_str());
  }
  {
    mps2::Text<200> t;
    t << "estimate: a = [";
    t.fixed(g_estimate.a(0), 4) << ", ";
    t.fixed(g_estimate.a(1), 4) << "], b = [";
    t.fixed(g_estimate.b(0), 3) << ", ";
    t.fixed(g_estimate.b(1), 3) << "], F(V_1) = ";
    t.fixed(g_estimate.F(0), 4) << " (true 0.0124), rows " << g_estimate.ls.rows << '\n';
    mps2::semihosting::write(t.c_str());
  }
  mps2::semihosting::write(g_failures == 0 ? "lashid bench_estimator: done\n" : "lashid bench_estimator: FAILED\n");
  return g_failures == 0 ? 0 : 1;
}
