#include "lashid/report/report.hpp"

#include <cmath>
#include <optional>
#include <string>

#include <fmt/format.h>

namespace lashid::report {

using namespace lashid::sim;

namespace {

std::string truth_cell(const std::optional<double>& truth) { return truth ? fmt::format("{:>12.5g}", *truth) : ""; }

std::optional<double> at(const std::optional<Truth>& t, const std::vector<double> Truth::*field, std::size_t k) {
  if (!t || ((*t).*field).size() <= k) return std::nullopt;
  return ((*t).*field)[k];
}

}  // namespace

void print_scheme_result(const ExperimentConfig& config, const SchemeResult& r) {
  const bool dis = r.scheme == est::Scheme::kDescending;
  fmt::print("{} ({} border): n = {}, m = {}; {} step + {} pulse samples, {} regression rows; status: {}\n",
             dis ? "DIS" : "AIS", dis ? "descendent" : "ascendent", config.n, config.m, r.step_samples,
             r.pulse_samples, r.rows, est::to_string(r.status));
  if (r.status != est::Status::kOk) {
    // No solution, so no estimates (their zeros are initial values, not results).
    fmt::print("  no estimates: {} (reciprocal condition of the reduced normal matrix {:.3g})\n",
               est::to_string(r.status), r.rcond);
    return;
  }
  fmt::print("  residual variance {:.4g}, reciprocal condition of the reduced normal matrix {:.3g}\n",
             r.noise_variance, r.rcond);
  fmt::print("  {:<14}{:>12}{:>12}{:>12}\n", "parameter", "estimate", "std.err", config.truth ? "truth" : "");
  const std::optional<double> ybar_truth =
      config.truth ? (dis ? config.truth->ybar0_d : config.truth->ybar0_a) : std::nullopt;
  fmt::print("  {:<14}{:>12.5g}{:>12}{}\n", "ybar0", r.ybar0, "", truth_cell(ybar_truth));
  for (std::size_t i = 0; i < r.a.size(); ++i) {
    fmt::print("  {:<14}{:>12.5g}{:>12.2g}{}\n", fmt::format("a{}", i + 1), r.a[i],
               r.theta_std_error.empty() ? 0.0 : r.theta_std_error[i], truth_cell(at(config.truth, &Truth::a, i)));
  }
  for (std::size_t i = 0; i < r.b.size(); ++i) {
    fmt::print("  {:<14}{:>12.5g}{:>12}{}\n", fmt::format("b{}", i + 1), r.b[i], "",
               truth_cell(at(config.truth, &Truth::b, i)));
  }
  const auto& V = dis ? config.V_d : config.V_a;
  for (std::size_t j = 0; j < r.F.size(); ++j) {
    fmt::print("  {:<14}{:>12.5g}{:>12}{}\n", fmt::format("F({:g})", V[j]), r.F[j], "",
               truth_cell(at(config.truth, dis ? &Truth::F_d : &Truth::F_a, j)));
  }
}

}  // namespace lashid::report
