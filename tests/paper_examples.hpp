// The paper's two examples in closed form, as the tests' independent source of truth (not the simulator's code).
// Consistent reading of the paper (its typos: Table 1's b2 sign, (4.7)'s C_a sign, Table 5's first row) as
// stated in docs/paper-notes.md.
#pragma once

#include <array>
#include <cmath>
#include <vector>

namespace lashid::test {

// DIS example, Section 3.5: backlash, [v_m, v_M] = [-3, 4], scaled by K = 70.5.
struct DisExample {
  static constexpr int n = 2, m = 6;
  static constexpr double v_min = -3, v_max = 4;
  static constexpr std::array<double, 2> a{1.0, 0.21};
  static constexpr std::array<double, 2> b{70.5, -35.25};
  static constexpr std::array<double, 6> V{-3, -2, -1, 1, 2, 3};
  static constexpr double noise_variance = 16;
  static double C_d(double v) { return (v * v * v + 3.5 * v * v + 2.75 * v + 4.625) / 70.5; }
  static double C_a(double v) { return C_d(v - 1); }
  static double u_M() { return C_a(v_max); }  // 71.375 / 70.5
  static double u_m() { return C_d(v_min); }  // 0.875 / 70.5
  // F^d of (3.2): C_d(V) below max C_d^-1(u_M) = 3 (the cubic's only real root of C_d(v) = u_M), u_M above.
  static double F_d(double v) { return v <= 3.0 ? C_d(v) : u_M(); }
};

// AIS example, Section 4.2: switch, [v_m, v_M] = [-2, 2], scaled by K = log(52) - log(3).
struct AisExample {
  static constexpr int n = 2, m = 6;
  static constexpr double v_min = -2, v_max = 2;
  static double K() { return std::log(52.0) - std::log(3.0); }  // u_M - u_m before scaling = 2.8526
  static std::array<double, 2> a() { return {-1.25, 0.375}; }
  static std::array<double, 2> b() { return {4 * K(), -K()}; }
  static constexpr std::array<double, 6> V{2, 1.5, 1, 0, -0.5, -1};
  static constexpr double noise_variance = 0.15;
  static double C_a(double v) { return std::log(-4 * v * v * v + 27 * v + 30) / K(); }
  static double C_d(double v) { return std::log(4 * v * v * v - 12 * v * v - 15 * v + 53) / K(); }
  static double u_M() { return C_a(v_max); }
  static double u_m() { return C_d(v_min); }
  // F^a of the AP experiment: a pulse up to V lands on C_a(V); the return to the held level v_m is a decrease, so
  // the switch sits at C_d(v_m) = u_m there.
  static double F_a(double v) { return v == v_min ? u_m() : C_a(v); }
};

// Theta from the closed form: [a1, a2, b1 c1, b2 c1, ..., b1 c6, b2 c6], c_j = (F(V_j) - F(held)) / W_j.
template <class Example, class F>
std::vector<double> closed_form_theta(std::array<double, 2> a, std::array<double, 2> b, double held_level,
                                      double held_output, F border) {
  std::vector<double> theta{a[0], a[1]};
  for (double V : Example::V) {
    const double c = (border(V) - held_output) / (V - held_level);
    theta.push_back(b[0] * c);
    theta.push_back(b[1] * c);
  }
  return theta;
}

}  // namespace lashid::test
