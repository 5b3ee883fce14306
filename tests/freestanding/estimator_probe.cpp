// Instantiates the whole estimator as the firmware will (float, n = 2, m = 6, no exceptions, no RTTI) so that the
// symbol check next to it can prove the object needs no heap and no exception machinery.
#include "lashid/estimator/batch_ls.hpp"
#include "lashid/estimator/covariance_rls.hpp"
#include "lashid/estimator/cross_check.hpp"
#include "lashid/estimator/excitation.hpp"
#include "lashid/estimator/identifier.hpp"

namespace {
lashid::est::SchemeIdentifier<float, 2, 6> g_identifier;
lashid::est::SchemeIdentifier<float, 2, 6, lashid::est::CovarianceRls> g_textbook;
lashid::est::SchemeIdentifier<double, 2, 6, lashid::est::BatchLeastSquares> g_batch;
}  // namespace

// Runs one identification on samples supplied by the caller; returns the status and the first border point.
extern "C" int lashid_estimator_probe(const float* y, int count, float* first_point) {
  lashid::est::ExperimentDesign<float, 6> d;
  d.v_min = -3.0f;
  d.v_max = 4.0f;
  d.V << -3.0f, -2.0f, -1.0f, 1.0f, 2.0f, 3.0f;
  if (g_identifier.configure(d) != lashid::est::Status::kOk) return -1;
  (void)g_textbook.configure(d);
  lashid::est::ExperimentDesign<double, 6> dd;
  dd.v_min = -3.0;
  dd.v_max = 4.0;
  dd.V << -3.0, -2.0, -1.0, 1.0, 2.0, 3.0;
  (void)g_batch.configure(dd);
  lashid::est::ExcitationGenerator<float, 2, 6> gen(d);
  gen.restart(count / 2);
  for (int t = 0; t < count; ++t) {
    const bool step = gen.in_step_experiment();
    const float v = gen.next();
    if (step) {
      (void)g_identifier.add_step_sample(v, y[t]);
      (void)g_textbook.add_step_sample(v, y[t]);
      (void)g_batch.add_step_sample(static_cast<double>(v), static_cast<double>(y[t]));
    } else {
      (void)g_identifier.add_pulse_sample(v, y[t]);
      (void)g_textbook.add_pulse_sample(v, y[t]);
      (void)g_batch.add_pulse_sample(static_cast<double>(v), static_cast<double>(y[t]));
    }
  }
  const auto e = g_identifier.estimate();
  const auto t = g_textbook.estimate();
  const auto b = g_batch.estimate();
  // Remark 3b between two back-ends' estimates: the firmware's cross-check code is in the checked object too.
  const float se[2] = {lashid::est::b_std_error(e.ls.std_error(2), -3.0f, 4.0f), t.ls.std_error(0)};
  const lashid::est::LinearEstimate<float> x{{e.a.data(), 2}, se, {e.b.data(), 2}, se};
  const lashid::est::LinearEstimate<float> z{{t.a.data(), 2}, se, {t.b.data(), 2}, se};
  *first_point = e.F(0) + t.F(0) + static_cast<float>(b.F(0)) + lashid::est::cross_check(x, z).max_z;
  return static_cast<int>(e.status);
}
