// Experiment design of the DIS (Section 3) and AIS (Section 4) of
//   F. Giri, Y. Rochdi, A. Brouri, F.Z. Chaoui, "Identification of block-oriented systems in the presence of
//   nonparametric input nonlinearities of switch and backlash types", Automatica.
//
// DIS: between pulses the input is held at v_M and the pulses go down to V_j^d, v_m = V_1^d < ... < V_m^d < v_M.
// AIS: between pulses the input is held at v_m and the pulses go up to V_j^a, v_M = V_1^a > ... > V_m^a > v_m.
// In both, W_j = V_j - (held level) and the model is scaled so that F~(W_1) = -1 (DIS, (3.11c)) or +1 (AIS, Remark 3a).
#pragma once

#include <cmath>
#include <cstdint>

#include <Eigen/Core>

#include "lashid/estimator/lagrange.hpp"
#include "lashid/estimator/status.hpp"

namespace lashid::est {

enum class Scheme : std::uint8_t {
  kDescending,  ///< DIS: points on the descendent border
  kAscending,   ///< AIS: points on the ascendent border
};

/// The longest pulse experiment the float32 estimator is held to: 2^28 = 268,435,456 rows (7.5 h at 10 kHz). Its
/// grouped sums lose accuracy beyond (the paper's DIS example, noise sd 4, float32 against double grouped least
/// squares: relative error of Theta 5.9e-5 at 10^7 rows and 5.7e-5 at 3.2e8, then 1.5e-4 at 6.4e8 and 8.2e-3 at
/// 1.28e9, with the status still kOk; measured in review, session 14, docs/estimator.md). The firmware refuses a
/// longer design (fw::DesignStatus::kPulseTooLong), and so does the host's config reader.
inline constexpr std::int64_t kMaxPulseLength = std::int64_t{1} << 28;

/// Period and pulse instants of Theorem 3.1, (3.25): T = n(m+3), tau_1 = 2n, tau_j = (2+j)n.
/// (3.1) also asks tau_j - tau_{j-1} >= 2, which (3.25) violates for n = 1 (spacing 1: consecutive pulses would
/// skip the return to the held level, so a backlash would move on a horizontal line, not on the border). We use
/// s = max(n, 2) in place of n in (3.25); for n >= 2 this is exactly the paper's schedule.
/// Run-time form (firmware, simulator, CLI); PulseSchedule below is the compile-time form (static checks, tests).
namespace schedule {
constexpr int spacing(int n) { return n < 2 ? 2 : n; }
constexpr int period(int n, int m) { return spacing(n) * (m + 3); }
/// tau_j for j = 1..m.
constexpr int tau(int n, int j) { return j == 1 ? 2 * spacing(n) : (2 + j) * spacing(n); }
/// Index j in 1..m of the pulse at `phase` = t mod T of the pulse experiment, or 0 when the input is held. O(1):
/// the pulses sit at multiples of the spacing s, tau_1 = 2s and tau_j = (2 + j)s for j >= 2.
constexpr int pulse_at_phase(int n, int m, int phase) {
  const int s = spacing(n);
  if (phase == 2 * s) return 1;
  if (phase % s != 0) return 0;
  const int j = phase / s - 2;
  return j >= 2 && j <= m ? j : 0;
}
/// Index j in 1..m of the pulse at sample t of the pulse experiment, or 0 when the input is held.
constexpr int pulse_at(int n, int m, std::int64_t t) {
  return pulse_at_phase(n, m, static_cast<int>(t % period(n, m)));
}
}  // namespace schedule

template <int N, int M>
struct PulseSchedule {
  static_assert(N >= 1 && N <= 8, "model order n must be in [1, 8]");
  static_assert(M >= 1 && M <= 16, "number of border points m must be in [1, 16]");
  static constexpr int kSpacing = schedule::spacing(N);
  static constexpr int kPeriod = schedule::period(N, M);

  static constexpr int tau(int j) { return schedule::tau(N, j); }
  static constexpr int pulse_at(std::int64_t t) { return schedule::pulse_at(N, M, t); }

  // Design rules of (3.1) checked at compile time; the grouped estimator relies on the spacing >= n
  // (at most one non-zero input entry per regressor row).
  static constexpr bool rules_hold() {
    if (tau(1) < 1 || tau(M) >= kPeriod) return false;
    for (int j = 2; j <= M; ++j) {
      if (tau(j) - tau(j - 1) < 2 || tau(j) - tau(j - 1) < N) return false;
    }
    return kPeriod - tau(M) >= N;  // the last pulse has left the n lags before the next period's first
  }
  static_assert(rules_hold(), "pulse schedule violates (3.1)/(3.25)");
};

/// Whether the classifier tells the m levels V[0..m-1] apart from each other (neighbours in the design's order) and
/// from the held level: every W_j = V_j - held, and every difference of neighbours, exceeds twice its tolerance (the
/// two nodes' bands must not touch). Levels that are strictly ordered but closer are taken for one another, or for
/// the held level: every sample classifies, and a point is never excited. V: the m levels (an Eigen vector's or a
/// std::array's data()).
template <class Scalar>
constexpr bool levels_resolvable(const Scalar* V, int m, Scalar held) {
  const auto magnitude = [](Scalar x) { return x < Scalar(0) ? -x : x; };
  Scalar scale = Scalar(0);
  for (int j = 0; j < m; ++j) {
    const Scalar w = magnitude(V[j] - held);
    if (w > scale) scale = w;
  }
  const Scalar tol = Scalar(2) * kLevelResolution<Scalar> * scale;
  for (int j = 0; j < m; ++j) {
    const Scalar w = V[j] - held;
    if (!(magnitude(w) > tol)) return false;
    if (j > 0 && !(magnitude(w - (V[j - 1] - held)) > tol)) return false;
  }
  return true;
}

/// The levels of one scheme. M is the capacity; the design uses the first m abscissas (m = M unless set).
template <class Scalar, int M>
struct ExperimentDesign {
  using Abscissas = Eigen::Matrix<Scalar, M, 1>;

  Scheme scheme = Scheme::kDescending;
  int m = M;  ///< number of abscissas used, 1..M
  Scalar v_min = Scalar(0);  ///< v_m
  Scalar v_max = Scalar(0);  ///< v_M
  Abscissas V = Abscissas::Zero();  ///< V_j^d (DIS) or V_j^a (AIS), j = 1..m, in the paper's order

  /// Level held between pulses: v_M for the DIS, v_m for the AIS.
  Scalar held_level() const { return scheme == Scheme::kDescending ? v_max : v_min; }
  /// Level of the first sample of the step experiment (3.4)/(4.1); afterwards the held level.
  Scalar step_start_level() const { return scheme == Scheme::kDescending ? v_min : v_max; }
  /// W_j = V_j - held level, (3.12) and (4.3), for j < m; zero past m.
  Abscissas W() const {
    Abscissas w = Abscissas::Zero();
    for (int j = 0; j < m && j < M; ++j) w(j) = V(j) - held_level();
    return w;
  }
  /// F~(W_1) after scaling: -1 for the DIS (3.11c), +1 for the AIS (Remark 3a).
  Scalar scaled_first_point() const { return scheme == Scheme::kDescending ? Scalar(-1) : Scalar(1); }

  Status validate() const {
    if (m < 1 || m > M) return Status::kOrderOutOfRange;
    if (!std::isfinite(v_min) || !std::isfinite(v_max) || !(v_min < v_max)) return Status::kIntervalInvalid;
    for (int j = 0; j < m; ++j) {
      if (!std::isfinite(V(j))) return Status::kAbscissasNotOrdered;
    }
    if (scheme == Scheme::kDescending) {
      if (V(0) != v_min || !(V(m - 1) < v_max)) return Status::kAbscissasNotOrdered;
      for (int j = 1; j < m; ++j) {
        if (!(V(j - 1) < V(j))) return Status::kAbscissasNotOrdered;
      }
    } else {
      if (V(0) != v_max || !(V(m - 1) > v_min)) return Status::kAbscissasNotOrdered;
      for (int j = 1; j < m; ++j) {
        if (!(V(j - 1) > V(j))) return Status::kAbscissasNotOrdered;
      }
    }
    if (!levels_resolvable(V.data(), m, held_level())) return Status::kAbscissasTooClose;
    return Status::kOk;
  }
};

/// Orders a runtime caller (CLI, config file) asks for must lie in the range it compiled: a status, not a crash.
constexpr Status check_orders(int n, int m, int max_n, int max_m) {
  return (n >= 1 && n <= max_n && m >= 1 && m <= max_m) ? Status::kOk : Status::kOrderOutOfRange;
}

}  // namespace lashid::est
