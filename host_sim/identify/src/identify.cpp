#include "lashid/identify/identify.hpp"

#include <span>
#include <vector>

#include <fmt/format.h>

#include "identify_dispatch.hpp"

namespace lashid::sim {

SchemeResult identify_scheme(const ExperimentConfig& config, const Recording& recording, est::Scheme scheme,
                             const IdentifyOptions& options, std::string_view data_name) {
  // The recursive estimator in both precisions: grouped least squares (estimator/grouped_rls.hpp).
  if (options.precision == Precision::kFloat) {
    return detail::run<float>(config, recording, scheme, data_name, options.leave_out_unusable_y);
  }
  return detail::run<double>(config, recording, scheme, data_name, options.leave_out_unusable_y);
}

est::CrossCheck<double> cross_check(const ExperimentConfig& config, const SchemeResult& dis, const SchemeResult& ais) {
  const std::size_t n = dis.a.size();
  // theta = [a_1..a_n, mu_11..mu_n1, ...] (recovery.hpp): se(a) and se(mu_.1) are its first 2n standard errors.
  if (dis.theta_std_error.size() < 2 * n || ais.theta_std_error.size() < 2 * n) {
    est::CrossCheck<double> c;
    c.status = est::Status::kNotExcited;
    return c;
  }
  std::vector<double> se_b_dis(n), se_b_ais(n);
  for (std::size_t i = 0; i < n; ++i) {
    se_b_dis[i] = est::b_std_error(dis.theta_std_error[n + i], config.v_min, config.v_max);
    se_b_ais[i] = est::b_std_error(ais.theta_std_error[n + i], config.v_min, config.v_max);
  }
  const auto part = [n](const SchemeResult& r, const std::vector<double>& se_b) {
    return est::LinearEstimate<double>{r.a, std::span<const double>(r.theta_std_error.data(), n), r.b, se_b};
  };
  return est::cross_check(part(dis, se_b_dis), part(ais, se_b_ais));
}

}  // namespace lashid::sim
