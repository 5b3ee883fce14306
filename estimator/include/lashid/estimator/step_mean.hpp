// Mean of the step-experiment output, (3.6)-(3.7), in O(1) memory.
//
// A(1) ybar_0 = B(1) u_M (DIS) or B(1) u_m (AIS): the mean over t = 1..L is the only use of the step response.
// The sample at t = 0 is skipped: its input is the opposite bound, the held level starts at t = 1.
// Welford's update keeps the mean accurate in float32 whatever the output's offset (a plain running sum of
// 10^5 samples around 26 would lose about three digits).
#pragma once

#include <cmath>
#include <cstdint>

#include "lashid/estimator/status.hpp"

namespace lashid::est {

template <class Scalar>
class StepMean {
 public:
  /// Adds y(t) of the step experiment; t counts from 0 within the experiment. A y the sums cannot take (NaN,
  /// infinite, or beyond kMaxSampleMagnitude: one 2e19 overflows the float32 m2) is refused as kNonFinite.
  Status add(std::int64_t t, Scalar y) {
    if (!usable(y)) return Status::kNonFinite;
    if (t == 0) return Status::kOk;
    ++count_;
    const Scalar delta = y - mean_;
    mean_ += delta / static_cast<Scalar>(count_);
    m2_ += delta * (y - mean_);
    return Status::kOk;
  }

  std::uint32_t count() const { return count_; }
  bool ready() const { return count_ > 0; }
  Scalar mean() const { return mean_; }
  /// Sample variance of y over the held part (includes the transient; an upper bound on the noise's share).
  Scalar variance() const { return count_ > 1 ? m2_ / static_cast<Scalar>(count_ - 1) : Scalar(0); }

 private:
  std::uint32_t count_ = 0;
  Scalar mean_ = Scalar(0);
  Scalar m2_ = Scalar(0);
};

}  // namespace lashid::est
