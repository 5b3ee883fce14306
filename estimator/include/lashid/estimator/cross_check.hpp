// Remark 3b: the DIS and the AIS identify the same linear subsystem A(q^-1), B(q^-1) (the operator differs, the
// linear block does not). Their estimates of a and b must agree within their uncertainty; a disagreement means the
// nonlinearity is not the assumed switch/backlash (e.g. dynamics before it). One definition for the firmware's
// kCrossCheck report and the host's diagnosis. Header-only, heap-free, no I/O.
#pragma once

#include <cmath>
#include <cstddef>
#include <span>

#include "lashid/estimator/status.hpp"

namespace lashid::est {

/// se(b_i) = |W_1| se(mu_i1): b_i = s mu_i1 W_1 by (3.22a) / Remark 3a, and |W_1| = v_M - v_m in both schemes.
template <class Scalar>
constexpr Scalar b_std_error(Scalar se_mu_i1, Scalar v_min, Scalar v_max) {
  return (v_max - v_min) * se_mu_i1;
}

/// One scheme's linear subsystem with its standard errors, n entries each (a_1..a_n, b_1..b_n).
template <class Scalar>
struct LinearEstimate {
  std::span<const Scalar> a, se_a, b, se_b;
};

template <class Scalar>
struct CrossCheck {
  Status status = Status::kOk;  ///< kOrderOutOfRange if the two estimates do not have the same n entries
  Scalar max_z = Scalar(0);     ///< max over a and b of |x_DIS - x_AIS| / sqrt(se_DIS^2 + se_AIS^2)
  int worst = 0;                ///< index of the largest z: 0..n-1 = a_{k+1}, n..2n-1 = b_{k-n+1}
};

/// z of every a_i and b_i in units of the combined standard error of the two (independent) experiments; the largest
/// one and where it is. A z that is NaN (zero standard errors) never becomes the maximum.
template <class Scalar>
CrossCheck<Scalar> cross_check(const LinearEstimate<Scalar>& dis, const LinearEstimate<Scalar>& ais) {
  CrossCheck<Scalar> c;
  const std::size_t n = dis.a.size();
  for (const auto* s : {&dis.se_a, &dis.b, &dis.se_b, &ais.a, &ais.se_a, &ais.b, &ais.se_b}) {
    if (s->size() != n) {
      c.status = Status::kOrderOutOfRange;
      return c;
    }
  }
  for (std::size_t k = 0; k < 2 * n; ++k) {
    const bool is_a = k < n;
    const std::size_t i = is_a ? k : k - n;
    const Scalar xd = is_a ? dis.a[i] : dis.b[i];
    const Scalar xa = is_a ? ais.a[i] : ais.b[i];
    const Scalar sd = is_a ? dis.se_a[i] : dis.se_b[i];
    const Scalar sa = is_a ? ais.se_a[i] : ais.se_b[i];
    const Scalar z = std::fabs(xd - xa) / std::sqrt(sd * sd + sa * sa);
    if (z > c.max_z) {
      c.max_z = z;
      c.worst = static_cast<int>(k);
    }
  }
  return c;
}

}  // namespace lashid::est
