#include "lashid/report/report.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "lashid/report/border_check.hpp"

namespace lashid::report {

using namespace lashid::sim;

namespace {

std::string truth_cell(const std::optional<double>& truth) { return truth ? fmt::format("{:>12.5g}", *truth) : ""; }

std::optional<double> at(const std::optional<Truth>& t, const std::vector<double> Truth::*field, std::size_t k) {
  if (!t || ((*t).*field).size() <= k) return std::nullopt;
  return ((*t).*field)[k];
}

}  // namespace

std::vector<std::string> level_labels(const std::vector<double>& levels) {
  std::vector<std::string> labels(levels.size());
  for (int digits = 6; digits <= 17; ++digits) {
    for (std::size_t j = 0; j < levels.size(); ++j) labels[j] = fmt::format("F({:.{}g})", levels[j], digits);
    if (std::set<std::string>(labels.begin(), labels.end()).size() == labels.size()) return labels;
  }
  // Equal levels (never in a valid config): the shortest form that reads back as each value.
  for (std::size_t j = 0; j < levels.size(); ++j) labels[j] = fmt::format("F({})", levels[j]);
  return labels;
}

void print_scheme_result(const ExperimentConfig& config, const SchemeResult& r) {
  const bool dis = r.scheme == est::Scheme::kDescending;
  fmt::print("{} ({} border): n = {}, m = {}; {} step + {} pulse samples, {} regression rows; status: {}\n",
             dis ? "DIS" : "AIS", dis ? "descendent" : "ascendent", config.n, config.m, r.step_samples,
             r.pulse_samples, r.rows, est::to_string(r.status));
  if (const std::string warning = border_warning(check_border(config, r)); !warning.empty()) {
    fmt::print("  {}\n", warning);
  }
  if (r.status != est::Status::kOk) {
    // No solution, so no estimates (their zeros are initial values, not results).
    fmt::print("  no estimates: {} (reciprocal condition of the reduced normal matrix {:.3g})\n",
               est::to_string(r.status), r.rcond);
    return;
  }
  // The label column fits the longest level label (levels far from 0 on a narrow interval need many digits).
  const std::vector<std::string> labels = level_labels(dis ? config.V_d : config.V_a);
  std::size_t width = 14;
  for (const std::string& label : labels) width = std::max(width, label.size() + 2);
  fmt::print("  residual variance {:.4g}, reciprocal condition of the reduced normal matrix {:.3g}\n",
             r.noise_variance, r.rcond);
  fmt::print("  {:<{}}{:>12}{:>12}{:>12}\n", "parameter", width, "estimate", "std.err", config.truth ? "truth" : "");
  const std::optional<double> ybar_truth =
      config.truth ? (dis ? config.truth->ybar0_d : config.truth->ybar0_a) : std::nullopt;
  fmt::print("  {:<{}}{:>12.5g}{:>12}{}\n", "ybar0", width, r.ybar0, "", truth_cell(ybar_truth));
  for (std::size_t i = 0; i < r.a.size(); ++i) {
    fmt::print("  {:<{}}{:>12.5g}{:>12.2g}{}\n", fmt::format("a{}", i + 1), width, r.a[i],
               r.theta_std_error.empty() ? 0.0 : r.theta_std_error[i], truth_cell(at(config.truth, &Truth::a, i)));
  }
  for (std::size_t i = 0; i < r.b.size(); ++i) {
    fmt::print("  {:<{}}{:>12.5g}{:>12}{}\n", fmt::format("b{}", i + 1), width, r.b[i], "",
               truth_cell(at(config.truth, &Truth::b, i)));
  }
  for (std::size_t j = 0; j < std::min(labels.size(), r.F.size()); ++j) {
    fmt::print("  {:<{}}{:>12.5g}{:>12}{}\n", labels[j], width, r.F[j], "",
               truth_cell(at(config.truth, dis ? &Truth::F_d : &Truth::F_a, j)));
  }
}

}  // namespace lashid::report
