// One identification scheme (DIS or AIS) end to end, one sample at a time: step experiment -> mean (3.7);
// pulse experiment -> centred signals (3.9a)/(4.3) -> regressor (3.19b) -> least squares -> recovery (3.22)-(3.23).
// The estimate is available at any time. Heap-free, no I/O; the least-squares back-end is a template parameter
// (GroupedLeastSquares: the recursive estimator; BatchLeastSquares: the (3.21) reference; CovarianceRls: the
// textbook baseline).
// N and M are capacities (fixed-size storage): configure() chooses the order n <= N; the design's m <= M.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "lashid/estimator/design.hpp"
#include "lashid/estimator/grouped_rls.hpp"
#include "lashid/estimator/recovery.hpp"
#include "lashid/estimator/regressor.hpp"
#include "lashid/estimator/step_mean.hpp"

namespace lashid::est {

template <class Scalar, int N, int M, template <class, int, int> class Solver = GroupedLeastSquares>
class SchemeIdentifier {
 public:
  using Design = ExperimentDesign<Scalar, M>;
  using Builder = RegressorBuilder<Scalar, N, M>;
  using Estimate = SchemeEstimate<Scalar, N, M>;
  using LeastSquares = Solver<Scalar, N, M>;

  SchemeIdentifier() = default;

  /// Validates the design and the order n, and clears all state. Until it succeeds every add_* returns
  /// kNotConfigured. kOrderOutOfRange for n outside [1, N] or a back-end that needs n = N, m = M.
  Status configure(const Design& design, int n = N) {
    configured_ = false;
    step_ = StepMean<Scalar>{};  // first: while not configured, the step mean is never ready (add_pulse_sample)
    if (n < 1 || n > N) return Status::kOrderOutOfRange;
    const Status s = design.validate();
    if (s != Status::kOk) return s;
    design_ = design;
    held_ = design.held_level();
    builder_ = Builder(design.W(), n, design.m);
    if (solver_.reset(design.W(), n, design.m) != Status::kOk) return Status::kOrderOutOfRange;
    step_t_ = 0;
    pulse_t_ = 0;
    configured_ = true;
    return Status::kOk;
  }

  /// Sample t of the step experiment (3.4)/(4.1). v must be the opposite bound at t = 0, the held level after.
  /// An off-design or non-finite sample is not used, but still advances t.
  Status add_step_sample(Scalar v, Scalar y) {
    if (!configured_) return Status::kNotConfigured;
    const std::int64_t t = step_t_++;
    if (!std::isfinite(v) || !usable(y)) return Status::kNonFinite;
    const int expected = t == 0 ? 0 : Builder::Basis::kZero;  // W_1 is the opposite bound in both schemes
    if (builder_.basis().classify(v - design_.held_level()) != expected) return Status::kInputOffDesign;
    return step_.add(t, y);
  }

  /// Sample t of the pulse experiment (3.1)/(4.2). Requires the step mean. Rows whose lags hold an off-design or
  /// non-finite sample are skipped (and reported); the estimate stays the least squares on the rows used.
  Status add_pulse_sample(Scalar v, Scalar y) {
    // One test on the path of every sample: not configured implies no step mean (configure() clears it first).
    if (!step_.ready()) return configured_ ? Status::kStepMeanMissing : Status::kNotConfigured;
    ++pulse_t_;
    const Scalar v_tilde = v - held_;
    // A y that is not usable (too large for the sums, NaN or infinite) becomes a NaN here, so that it and every row
    // holding it as a lag are skipped as a NaN's are.
    const Scalar y_tilde = usable(y) ? y - step_.mean() : std::numeric_limits<Scalar>::quiet_NaN();
    Status s = Status::kOk;
    bool took_row = false;
    // One dispatch on the order for the whole sample: the builder's and the solver's kernels compiled for n.
    with_order<N>(builder_.order(), [&](auto order) {
      constexpr int Nn = decltype(order)::value;
      if (builder_.ready()) {
        if constexpr (requires(SparseRegressor<Scalar, N, M> r) { solver_.template update_n<Nn>(r, y_tilde); }) {
          SparseRegressor<Scalar, N, M> row;
          s = builder_.template sparse_n<Nn>(row);
          if (s == Status::kOk) s = solver_.template update_n<Nn>(row, y_tilde);
        } else {
          s = solver_.update(builder_, y_tilde);
        }
        took_row = true;
      }
      builder_.template push_n<Nn>(v_tilde, y_tilde);
    });
    if (s != Status::kOk) return s;
    // A row taken had a finite target (every solver refuses a NaN one): only without a row is y_tilde checked here.
    // (This check on every sample paid for the magnitude rule above: docs/on-target-cost.md.)
    if (!took_row && !finite(y_tilde)) return Status::kNonFinite;
    // A NaN or infinite v is never a design level: classified off the design, it is told apart only here.
    if (builder_.newest_class() == Builder::Basis::kOffDesign) {
      return finite(v) ? Status::kInputOffDesign : Status::kNonFinite;
    }
    return Status::kOk;
  }

  /// Current estimate. status is kOk only if Theta was solved and recovered. with_std_errors = false skips the
  /// standard errors and the residual variance (the back-ends that always compute them ignore it).
  Estimate estimate(bool with_std_errors = true) const {
    Estimate e;
    estimate_into(e, with_std_errors);
    return e;
  }

  /// estimate() into `e`, writing only the entries of this n and m (a, b: n; c, F: m; Theta: n + n m) where the
  /// back-end allows it: what the firmware does every pulse period, without clearing or copying the capacity.
  void estimate_into(Estimate& e, bool with_std_errors = true) const {
    e.scheme = design_.scheme;
    e.ybar0 = step_.mean();
    if (!configured_) {
      e.status = Status::kNotConfigured;
      return;
    }
    if (!step_.ready()) {
      e.status = Status::kStepMeanMissing;
      return;
    }
    if constexpr (requires { solver_.solve_into(e.ls, with_std_errors); }) {
      solver_.solve_into(e.ls, with_std_errors);
    } else if constexpr (requires { solver_.solve(with_std_errors); }) {
      e.ls = solver_.solve(with_std_errors);
    } else {
      e.ls = solver_.solve();
    }
    if (e.ls.status != Status::kOk) {
      e.status = e.ls.status;
      return;
    }
    e.status = recover(design_, e);
  }

  const Design& design() const { return design_; }
  int order() const { return builder_.order(); }
  const StepMean<Scalar>& step_mean() const { return step_; }
  const LeastSquares& least_squares() const { return solver_; }
  std::int64_t step_samples() const { return step_t_; }
  std::int64_t pulse_samples() const { return pulse_t_; }

 private:
  Design design_{};
  Scalar held_ = Scalar(0);  // design_.held_level(), read every sample
  Builder builder_{typename Builder::Basis::Nodes(Builder::Basis::Nodes::Ones())};
  LeastSquares solver_{};
  StepMean<Scalar> step_{};
  std::int64_t step_t_ = 0;
  std::int64_t pulse_t_ = 0;
  bool configured_ = false;
};

}  // namespace lashid::est
