// One identification scheme (DIS or AIS) end to end, one sample at a time: step experiment -> mean (3.7);
// pulse experiment -> centred signals (3.9a)/(4.3) -> regressor (3.19b) -> least squares -> recovery (3.22)-(3.23).
// The estimate is available at any time. Heap-free, no I/O; the least-squares back-end is a template parameter
// (GroupedLeastSquares: the recursive estimator; BatchLeastSquares: the (3.21) reference; CovarianceRls: the
// textbook baseline).
// N and M are capacities (fixed-size storage): configure() chooses the order n <= N; the design's m <= M.
#pragma once

#include <cmath>
#include <cstdint>

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
    if (n < 1 || n > N) return Status::kOrderOutOfRange;
    const Status s = design.validate();
    if (s != Status::kOk) return s;
    design_ = design;
    builder_ = Builder(design.W(), n, design.m);
    if (solver_.reset(design.W(), n, design.m) != Status::kOk) return Status::kOrderOutOfRange;
    step_ = StepMean<Scalar>{};
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
    if (!std::isfinite(v)) return Status::kNonFinite;
    const int expected = t == 0 ? 0 : Builder::Basis::kZero;  // W_1 is the opposite bound in both schemes
    if (builder_.basis().classify(v - design_.held_level()) != expected) return Status::kInputOffDesign;
    return step_.add(t, y);
  }

  /// Sample t of the pulse experiment (3.1)/(4.2). Requires the step mean. Rows whose lags hold an off-design or
  /// non-finite sample are skipped (and reported); the estimate stays the least squares on the rows used.
  Status add_pulse_sample(Scalar v, Scalar y) {
    if (!configured_) return Status::kNotConfigured;
    if (!step_.ready()) return Status::kStepMeanMissing;
    ++pulse_t_;
    const Scalar v_tilde = v - design_.held_level();
    const Scalar y_tilde = y - step_.mean();
    Status s = Status::kOk;
    if (builder_.ready()) s = solver_.update(builder_, y_tilde);
    builder_.push(v_tilde, y_tilde);
    if (s != Status::kOk) return s;
    if (!std::isfinite(v) || !std::isfinite(y)) return Status::kNonFinite;
    if (builder_.newest_class() == Builder::Basis::kOffDesign) return Status::kInputOffDesign;
    return Status::kOk;
  }

  /// Current estimate. status is kOk only if Theta was solved and recovered. with_std_errors = false skips the
  /// standard errors and the residual variance (the back-ends that always compute them ignore it).
  Estimate estimate(bool with_std_errors = true) const {
    Estimate e;
    e.scheme = design_.scheme;
    e.ybar0 = step_.mean();
    if (!configured_) {
      e.status = Status::kNotConfigured;
      return e;
    }
    if (!step_.ready()) {
      e.status = Status::kStepMeanMissing;
      return e;
    }
    if constexpr (requires { solver_.solve(with_std_errors); }) {
      e.ls = solver_.solve(with_std_errors);
    } else {
      e.ls = solver_.solve();
    }
    if (e.ls.status != Status::kOk) {
      e.status = e.ls.status;
      return e;
    }
    e.status = recover(design_, e);
    return e;
  }

  const Design& design() const { return design_; }
  int order() const { return builder_.order(); }
  const StepMean<Scalar>& step_mean() const { return step_; }
  const LeastSquares& least_squares() const { return solver_; }
  std::int64_t step_samples() const { return step_t_; }
  std::int64_t pulse_samples() const { return pulse_t_; }

 private:
  Design design_{};
  Builder builder_{typename Builder::Basis::Nodes(Builder::Basis::Nodes::Ones())};
  LeastSquares solver_{};
  StepMean<Scalar> step_{};
  std::int64_t step_t_ = 0;
  std::int64_t pulse_t_ = 0;
  bool configured_ = false;
};

}  // namespace lashid::est
