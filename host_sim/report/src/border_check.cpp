#include "lashid/report/border_check.hpp"

#include <cmath>
#include <cstddef>
#include <limits>

#include <fmt/format.h>

#include "lashid/stats/statistics.hpp"

namespace lashid::report {

BorderCheck check_border(const sim::SchemeResult& r, const std::vector<double>& levels, double held) {
  BorderCheck c;
  const std::size_t n = r.a.size(), m = r.F.size(), groups = n * m;
  if (r.status != est::Status::kOk || groups < 2 || levels.size() < m || r.theta.size() < n + groups ||
      r.theta_std_error.size() < n + groups) {
    return c;
  }
  // theta = [a_1..a_n, mu_11..mu_n1, mu_12..mu_n2, ...] (recovery.hpp): group k = (l, i) at n + l n + i.
  std::vector<double> x(groups), se(groups);
  double weights = 0, weighted = 0;
  bool exact = false;  // a standard error of 0: a noise-free fit
  for (std::size_t k = 0; k < groups; ++k) {
    const double W = std::fabs(levels[k / n] - held);
    x[k] = r.theta[n + k] * (levels[k / n] - held);
    se[k] = r.theta_std_error[n + k] * W;
    if (!(se[k] > 0)) {
      exact = true;
      continue;
    }
    weights += 1.0 / (se[k] * se[k]);
    weighted += x[k] / (se[k] * se[k]);
  }
  c.applicable = true;
  c.threshold = sim::stats::normal_quantile(1.0 - kFlatBorderAlpha / (2.0 * static_cast<double>(groups)));
  if (exact) {
    // Without noise any difference between the groups is real.
    bool equal = true;
    for (std::size_t k = 1; k < groups; ++k) equal = equal && x[k] == x[0];
    c.max_z = equal ? 0.0 : std::numeric_limits<double>::infinity();
  } else {
    const double mean = weighted / weights;
    for (std::size_t k = 0; k < groups; ++k) c.max_z = std::fmax(c.max_z, std::fabs(x[k] - mean) / se[k]);
  }
  c.flat = c.max_z <= c.threshold;
  return c;
}

BorderCheck check_border(const sim::ExperimentConfig& config, const sim::SchemeResult& r) {
  const bool dis = r.scheme == est::Scheme::kDescending;
  return check_border(r, dis ? config.V_d : config.V_a, dis ? config.v_max : config.v_min);
}

std::string border_warning(const BorderCheck& c) {
  if (!c.flat) return {};
  return fmt::format("WARNING: border not identified: no pulse moved the output distinguishably from the others "
                     "(largest z = {:.3g}, at most {:.3g}: the bound a flat border stays under with probability "
                     "{:g} %); F(V_j) is not distinguishable from a border constant over the levels: if it is also "
                     "flat at the held level, nothing was excited and b and F are noise (docs/data-format.md)",
                     c.max_z, c.threshold, 100.0 * (1.0 - kFlatBorderAlpha));
}

}  // namespace lashid::report
