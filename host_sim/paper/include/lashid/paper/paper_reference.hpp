// Numbers printed in the paper (Giri et al., Automatica; see estimator/design.hpp for the full reference), transcribed as data so that the reproduction command and
// the tests compare against the same figures. Where the paper is inconsistent with itself, the comment says so;
// docs/paper-notes.md has the full list and the evidence.
#pragma once

#include <array>

namespace lashid::sim::paper {

// Section 3.5.1, (3.33): DIS estimate of Theta^d, N = 2000.
inline constexpr std::array<double, 14> kDisTheta{1.0005,  0.2122,  10.0769, -5.0439, 11.1040, -5.5432, 13.4025,
                                                  -6.7368, 19.8480, -10.027, 19.8956, -10.0071, 0.6476, -0.0617};
inline constexpr double kDisYbar0 = 16.15;  // Section 3.5.1, L = 2000
// Table 1 (b2 printed as +35.25 / +35.27: the sign is a typo, (3.31) with (3.33) and Table 3 need -35.25).
// Table 1's estimates are not those of (3.33) (a2 0.2111 vs 0.2122; b1 = -7 mu_11 = 70.54 vs 70.48): another run.
inline constexpr std::array<double, 2> kDisTable1A{1.001, 0.2111};
inline constexpr std::array<double, 2> kDisTable1B{70.48, -35.27};
// Table 2: F^d(V_j) true and estimated, V^d = {-3, -2, -1, 1, 2, 3}.
inline constexpr std::array<double, 6> kDisTable2True{0.0124, 0.073, 0.062, 0.168, 0.456, 1.01};
inline constexpr std::array<double, 6> kDisTable2Estimate{0.0122, 0.068, 0.061, 0.167, 0.447, 1.00};
// Section 3.5.2: P(||Theta_hat - Theta|| / ||Theta|| < 0.02) over 100 and 1000 repetitions.
inline constexpr double kDisConsistencyEps = 0.02;
inline constexpr double kDisConsistencyP100 = 0.97;
inline constexpr double kDisConsistencyP1000 = 0.995;

// Table 3: DIS estimates with input dynamics G = (1-lambda)/(1-lambda q^-1) before the backlash.
// Columns: a1, a2, b1, b2, F~(V_2) .. F~(V_6) (F~ = F^d(V_j) - u_M = c_j W_j).
struct Table3Row {
  double lambda;
  std::array<double, 9> values;
};
inline constexpr std::array<double, 9> kTable3True{1, 0.21, 70.5, -35.3, -0.939, -0.950, -0.844, -0.557, 0};
inline constexpr std::array<Table3Row, 3> kTable3{{
    {0.0, {0.996, 0.21, 70.5, -35.4, -0.938, -0.9560, -0.844, -0.552, 0.002}},
    {0.005, {0.968, 0.19, 70.9, -34.0, -0.9343, -0.9564, -0.854, -0.565, -0.012}},
    {0.01, {1.04, 0.24, 67.7, -36.48, -0.9306, -0.955, -0.861, -0.575, -0.026}},
}};

// Section 4.2: AIS estimate of Theta^a, N = 8000.
inline constexpr std::array<double, 14> kAisTheta{-1.2517, 0.3764,  2.8500,  -0.7195, 3.3656,  -0.8502, 3.8295,
                                                  -0.9672, 4.6098,  -1.1602, 4.6213,  -1.1487, 3.3877,  -0.8719};
inline constexpr double kAisYbar0 = 26.37;
// Table 4 (again not the run of the printed Theta^a: a1 -1.2579 vs -1.2517).
inline constexpr std::array<double, 2> kAisTable4A{-1.2579, 0.3813};
inline constexpr std::array<double, 2> kAisTable4B{11.4146, -2.8528};
// Table 5: F^a(V_j) true and estimated. Its first row prints V = {4, 3, 2, 1, -1, -2}; the values are those of
// V^a = {2, 1.5, 1, 0, -0.5, -1} (Section 4.2's abscissas), e.g. C_a(2) = log(52)/K = 1.3851.
inline constexpr std::array<double, 6> kAisTable5True{1.3851, 1.4173, 1.3918, 1.1923, 0.9932, 0.6821};
inline constexpr std::array<double, 6> kAisTable5Estimate{1.3852, 1.4170, 1.3873, 1.1900, 0.9939, 0.6808};

}  // namespace lashid::sim::paper
