// `lashid reproduce`: the paper's two examples (Sections 3.5 and 4.2), Table 3 and the consistency check of
// Section 3.5.2, on the simulator, side by side with the paper's printed numbers and the truth.
#include <chrono>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "lashid/paper/paper_reference.hpp"
#include "lashid/paper/reproduction.hpp"
#include "lashid/report/json.hpp"
#include "lashid/report/report.hpp"
#include "lashid/stats/metrics.hpp"

namespace lashid::app {

using namespace lashid::sim;

namespace {

void print_theta(const SchemeResult& r, std::span<const double> paper_theta, const std::vector<double>& truth) {
  fmt::print("  {:<4}{:>11}{:>10}{:>11}{:>11}\n", "k", "ours", "std.err", "paper", "true");
  for (std::size_t k = 0; k < r.theta.size(); ++k) {
    fmt::print("  {:<4}{:>11.4f}{:>10.4f}{:>11.4f}{:>11.4f}\n", k + 1, r.theta[k], r.theta_std_error[k],
               paper_theta[k], truth[k]);
  }
  fmt::print("  ||ours - true|| / ||true|| = {:.4f}; ||paper - true|| / ||true|| = {:.4f}\n",
             stats::relative_difference(r.theta, truth), stats::relative_difference(paper_theta, truth));
}

void print_points(const char* title, const std::vector<double>& V, const std::vector<double>& truth,
                  std::span<const double> paper_true, const std::vector<double>& ours,
                  std::span<const double> paper_estimate) {
  fmt::print("  {}\n  {:<8}{:>10}{:>12}{:>10}{:>12}\n", title, "V_j", "true", "paper true", "ours", "paper est.");
  for (std::size_t j = 0; j < V.size(); ++j) {
    fmt::print("  {:<8g}{:>10.4f}{:>12.4f}{:>10.4f}{:>12.4f}\n", V[j], truth[j], paper_true[j], ours[j],
               paper_estimate[j]);
  }
}

// One of the paper's two examples and the numbers it prints.
struct PaperExample {
  const char* scenario;
  est::Scheme scheme;
  const char* title;
  const char* theta_label;
  std::span<const double> theta;
  double ybar0;
  const char* linear_table;
  std::span<const double> table_a, table_b;
  const char* border_table;
  std::span<const double> border_true, border_estimate;
};

// Identifies the example on the simulator and prints it beside the paper's numbers and the truth.
SchemeResult report_example(const PaperExample& x, const ScenarioRun& run) {
  const Scenario& s = find_scenario(x.scenario);
  const bool dis = x.scheme == est::Scheme::kDescending;
  const SchemeResult r = identify_scenario(s, x.scheme, run);
  fmt::print("== {}: {} (seed {}) ==\n", x.title, s.description, run.seed);
  report::print_scheme_result(s.config, r);
  fmt::print("  ybar0: ours {:.3f}, paper {:.2f}, true {:.3f}\n", r.ybar0, x.ybar0,
             *(dis ? s.config.truth->ybar0_d : s.config.truth->ybar0_a));
  fmt::print("  {}:\n", x.theta_label);
  print_theta(r, x.theta, true_theta(s.config, x.scheme));
  fmt::print("  {}: a = ({:.4f}, {:.4f}) paper ({}, {});  b = ({:.4f}, {:.4f}) paper ({}, {})\n", x.linear_table,
             r.a[0], r.a[1], x.table_a[0], x.table_a[1], r.b[0], r.b[1], x.table_b[0], x.table_b[1]);
  print_points(x.border_table, dis ? s.config.V_d : s.config.V_a, dis ? s.config.truth->F_d : s.config.truth->F_a,
               x.border_true, r.F, x.border_estimate);
  return r;
}

nlohmann::json summary_json(const MonteCarloSummary& mc) {
  return {{"runs", mc.runs},
          {"N", mc.pulse_length},
          {"eps", mc.eps},
          {"probability", mc.probability},
          {"mean_relative_error", mc.mean_relative_error},
          {"failures", mc.failures}};
}

}  // namespace

int run_reproduce(const ReproduceArgs& args) {
  const auto start = std::chrono::steady_clock::now();
  nlohmann::json out;
  const Scenario& dis_s = find_scenario("dis_paper");
  ScenarioRun run;
  run.seed = args.seed;

  const PaperExample dis_example{"dis_paper", est::Scheme::kDescending, "DIS, paper Section 3.5", "Theta^d, paper (3.33)",
                                 paper::kDisTheta, paper::kDisYbar0, "Table 1", paper::kDisTable1A,
                                 paper::kDisTable1B, "Table 2: F^d(V_j)", paper::kDisTable2True,
                                 paper::kDisTable2Estimate};
  const PaperExample ais_example{"ais_paper", est::Scheme::kAscending, "AIS, paper Section 4.2",
                                 "Theta^a, paper Section 4.2", paper::kAisTheta, paper::kAisYbar0, "Table 4",
                                 paper::kAisTable4A, paper::kAisTable4B, "Table 5: F^a(V_j)", paper::kAisTable5True,
                                 paper::kAisTable5Estimate};
  const SchemeResult dis = report_example(dis_example, run);
  out["dis"] = to_json(dis);
  fmt::print("\n");
  const SchemeResult ais = report_example(ais_example, run);
  out["ais"] = to_json(ais);

  // --- Table 3: input dynamics before the backlash ----------------------------------------------------------
  fmt::print("\n== Table 3: DIS with G = (1-lambda)/(1-lambda q^-1) before the backlash (same noise, seed {}) ==\n",
             args.seed);
  fmt::print("  {:<16}{:>8}{:>8}{:>8}{:>8}{:>9}{:>9}{:>9}{:>9}{:>9}\n", "", "a1", "a2", "b1", "b2", "F~(V2)",
             "F~(V3)", "F~(V4)", "F~(V5)", "F~(V6)");
  for (const auto& row : paper::kTable3) {
    ScenarioRun lag = run;
    lag.input_lag = row.lambda;
    const SchemeResult r = identify_scenario(dis_s, est::Scheme::kDescending, lag);
    const std::vector<double> ours{r.a[0],          r.a[1],          r.b[0],          r.b[1],         r.F_centered[1],
                                   r.F_centered[2], r.F_centered[3], r.F_centered[4], r.F_centered[5]};
    fmt::print("  {:<16}{:>8.3f}{:>8.3f}{:>8.2f}{:>8.2f}{:>9.4f}{:>9.4f}{:>9.4f}{:>9.4f}{:>9.4f}\n",
               fmt::format("ours l={}", row.lambda), ours[0], ours[1], ours[2], ours[3], ours[4], ours[5], ours[6],
               ours[7], ours[8]);
    const auto& p = row.values;
    fmt::print("  {:<16}{:>8.3f}{:>8.3f}{:>8.2f}{:>8.2f}{:>9.4f}{:>9.4f}{:>9.4f}{:>9.4f}{:>9.4f}\n",
               fmt::format("paper l={}", row.lambda), p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8]);
    out["table3"].push_back({{"lambda", row.lambda}, {"ours", ours}, {"paper", p}});
  }

  // --- Consistency, Section 3.5.2 ---------------------------------------------------------------------------
  fmt::print("\n== Consistency (Section 3.5.2): P(||Theta_hat - Theta|| / ||Theta|| < {}) over {} runs ==\n",
             paper::kDisConsistencyEps, args.runs);
  for (const int N : {2000, 20000}) {
    const MonteCarloSummary mc =
        monte_carlo(dis_s, est::Scheme::kDescending, args.runs, N, paper::kDisConsistencyEps, 1000);
    // The paper's smaller sample (100 runs) beside its larger one, when there are more than 100 runs.
    std::string first100;
    if (mc.relative_errors.size() > 100) {
      int hits = 0;
      for (std::size_t r = 0; r < 100; ++r) hits += mc.relative_errors[r] < mc.eps;
      first100 = fmt::format(" (first 100 runs: {:.2f})", hits / 100.0);
    }
    fmt::print("  N = {:>5}: P = {:.3f}{}, mean relative error {:.4f}, {} failed runs\n", N, mc.probability,
               first100, mc.mean_relative_error, mc.failures);
    out["consistency"].push_back(summary_json(mc));
  }
  fmt::print("  paper, N = 2000: P = {} (100 runs), {} (1000 runs)\n", paper::kDisConsistencyP100,
             paper::kDisConsistencyP1000);

  // --- float32 (the firmware's precision) vs double ---------------------------------------------------------
  ScenarioRun f32 = run;
  f32.precision = Precision::kFloat;
  const double dis_f = stats::relative_difference(identify_scenario(dis_s, est::Scheme::kDescending, f32).theta, dis.theta);
  const double ais_f =
      stats::relative_difference(identify_scenario(find_scenario("ais_paper"), est::Scheme::kAscending, f32).theta, ais.theta);
  fmt::print("\n== float32 recursive estimate vs double: ||dTheta|| / ||Theta|| = {:.2g} (DIS), {:.2g} (AIS) ==\n",
             dis_f, ais_f);
  out["float32_relative_difference"] = {{"dis", dis_f}, {"ais", ais_f}};

  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  fmt::print("\nreproduce finished in {:.1f} s\n", seconds);
  if (!args.json_out.empty()) write_json_file(args.json_out, out);
  return dis.status == est::Status::kOk && ais.status == est::Status::kOk ? 0 : 2;
}

}  // namespace lashid::app
