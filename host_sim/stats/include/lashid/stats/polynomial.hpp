// Monic polynomials z^n + a_1 z^(n-1) + ... + a_n, as the denominators A(q^-1) = 1 + a_1 q^-1 + ... + a_n q^-n of
// the models' linear parts: their roots (the poles), the polynomial from its roots, stability, and the stable
// polynomial with the same magnitude response up to a constant (unstable roots reflected into the unit circle).
#pragma once

#include <complex>
#include <vector>

namespace lashid::sim::stats {

/// The roots of z^n + a_1 z^(n-1) + ... + a_n (the eigenvalues of its companion matrix); empty for n = 0.
std::vector<std::complex<double>> polynomial_roots(const std::vector<double>& a);

/// a_1..a_n of prod_k (z - r_k). Complex roots must come in conjugate pairs (the imaginary parts then cancel and
/// are dropped).
std::vector<double> polynomial_from_roots(const std::vector<std::complex<double>>& roots);

/// Whether every root of z^n + a_1 z^(n-1) + ... + a_n lies strictly inside the unit circle.
bool is_stable(const std::vector<double>& a);

/// a with every root r on or outside the unit circle replaced by 1 / conj(r): A(z) times an all-pass factor, so
/// |A(e^jw)| changes only by a constant (Ljung, System Identification, 2nd ed., Sec. 10.3, stabilising a predictor
/// before a search). Returns a unchanged when it is stable. A root on the circle stays on it.
std::vector<double> reflected_into_unit_circle(const std::vector<double>& a);

}  // namespace lashid::sim::stats
