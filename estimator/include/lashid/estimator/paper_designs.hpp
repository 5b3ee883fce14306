// The experiment designs of the paper's two examples: model order, working interval, abscissas and experiment
// lengths. The one source of these numbers for the firmware's configurations
// (firmware/include/lashid/firmware/paper_run_designs.hpp) and the simulator's scenarios dis_paper and ais_paper
// (host_sim/sim), which add the plants (borders, A, B, noise).
// Header-only constexpr data, heap-free.
#pragma once

#include <array>
#include <cstddef>

namespace lashid::est::paper {

/// Both schemes' experiments on one actuator: the DIS (3.1)/(3.4) and the AIS (4.1)/(4.2).
template <class Scalar, std::size_t M>
struct Design {
  static constexpr int m = static_cast<int>(M);  ///< number of border points
  int n = 0;                    ///< model order
  Scalar v_min = Scalar(0);     ///< v_m
  Scalar v_max = Scalar(0);     ///< v_M
  std::array<Scalar, M> V_d{};  ///< V_1^d .. V_m^d, (3.1): v_m = V_1^d < ... < V_m^d < v_M
  std::array<Scalar, M> V_a{};  ///< V_1^a .. V_m^a, (4.2): v_M = V_1^a > ... > V_m^a > v_m
  int step_length = 0;          ///< L of both step experiments (3.4)/(4.1): L + 1 samples, t = 0..L
  int pulse_length_d = 0;       ///< N of the DP experiment
  int pulse_length_a = 0;       ///< N of the AP experiment
};

/// Section 3.5: backlash, [v_m, v_M] = [-3, 4], L = N = 2000. V_a is not in the paper (it ran only the DIS on this
/// plant): symmetric to V_d. Table 5's mislabelled first row reads exactly these abscissas.
template <class Scalar>
inline constexpr Design<Scalar, 6> kDisPaper{
    .n = 2,
    .v_min = Scalar(-3),
    .v_max = Scalar(4),
    .V_d = {Scalar(-3), Scalar(-2), Scalar(-1), Scalar(1), Scalar(2), Scalar(3)},
    .V_a = {Scalar(4), Scalar(3), Scalar(2), Scalar(1), Scalar(-1), Scalar(-2)},
    .step_length = 2000,
    .pulse_length_d = 2000,
    .pulse_length_a = 2000,
};

/// Section 4.2: switch, [v_m, v_M] = [-2, 2], L = 2000, N = 8000. Table 5's true values sit at these V_a (its
/// first row does not); V_d is not in the paper: symmetric to V_a.
template <class Scalar>
inline constexpr Design<Scalar, 6> kAisPaper{
    .n = 2,
    .v_min = Scalar(-2),
    .v_max = Scalar(2),
    .V_d = {Scalar(-2), Scalar(-1.5), Scalar(-1), Scalar(0), Scalar(0.5), Scalar(1)},
    .V_a = {Scalar(2), Scalar(1.5), Scalar(1), Scalar(0), Scalar(-0.5), Scalar(-1)},
    .step_length = 2000,
    .pulse_length_d = 8000,
    .pulse_length_a = 8000,
};

}  // namespace lashid::est::paper
