// Host check of the consumer: a known plant, the paper's DIS inputs, the estimates against the plant's numbers.
// The plant: a static nonlinearity u = (v + 3) / 7 (a switch whose two borders coincide; u_m = 0, u_M = 1) and the
// linear part of the paper's Section 3.5, A = 1 + q^-1 + 0.21 q^-2, B = 70.5 q^-1 - 35.25 q^-2, no noise.
// A is scale-free and so is b2 / b1 = -0.5: both must come back (to the O(1/L) start-up bias of the step mean).
#include <cmath>
#include <cstdio>
#include <vector>

#include <lashid/estimator.hpp>

#include "estimate_from_arrays.hpp"

int main() {
  namespace est = lashid::est;
  constexpr auto& paper = est::paper::kDisPaper<float>;
  est::ExperimentDesign<float, 6> design;
  design.scheme = est::Scheme::kDescending;
  design.v_min = paper.v_min;
  design.v_max = paper.v_max;
  for (int j = 0; j < 6; ++j) design.V(j) = paper.V_d[static_cast<unsigned>(j)];
  const est::ExcitationGenerator<float, 2, 6> inputs(design, paper.n);

  double y1 = 0, y2 = 0, u1 = 0, u2 = 0;
  const auto plant = [&](float v) {
    const double u = (static_cast<double>(v) + 3.0) / 7.0;
    const double y = -1.0 * y1 - 0.21 * y2 + 70.5 * u1 - 35.25 * u2;
    y2 = y1;
    y1 = y;
    u2 = u1;
    u1 = u;
    return static_cast<float>(y);
  };
  std::vector<float> vs, ys, vp, yp;
  for (int t = 0; t <= paper.step_length; ++t) {
    vs.push_back(inputs.step_input(t));
    ys.push_back(plant(vs.back()));
  }
  for (int t = 0; t < paper.pulse_length_d; ++t) {
    vp.push_back(inputs.pulse_input(t));
    yp.push_back(plant(vp.back()));
  }
  const consumer::DisResult r = consumer::identify_dis(vs.data(), ys.data(), static_cast<int>(vs.size()), vp.data(),
                                                       yp.data(), static_cast<int>(vp.size()));
  std::printf("status %d, a = [%.4f, %.4f], b = [%.3f, %.3f], b2/b1 = %.4f\n", r.status, static_cast<double>(r.a[0]),
              static_cast<double>(r.a[1]), static_cast<double>(r.b[0]), static_cast<double>(r.b[1]),
              static_cast<double>(r.b[1] / r.b[0]));
  const bool ok = r.status == 0 && std::fabs(r.a[0] - 1.0f) < 0.01f && std::fabs(r.a[1] - 0.21f) < 0.01f &&
                  std::fabs(r.b[1] / r.b[0] + 0.5f) < 0.01f;
  std::printf("%s\n", ok ? "consumer: ok" : "consumer: WRONG ESTIMATE");
  return ok ? 0 : 1;
}
