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
#include "lashid/sim/paper_reference.hpp"
#include "lashid/sim/reproduction.hpp"
#include "report.hpp"

namespace lashid::app {

using namespace lashid::sim;

namespace {

double relative_difference(std::span<const double> x, std::span<const double> ref) {
  double num = 0, den = 0;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    num += (x[k] - ref[k]) * (x[k] - ref[k]);
    den += ref[k] * ref[k];
  }
  return std::sqrt(num / den);
}

void print_theta(const SchemeResult& r, std::span<const double> paper_theta, const std::vector<double>& truth) {
  fmt::print("  {:<4}{:>11}{:>10}{:>11}{:>11}\n", "k", "ours", "std.err", "paper", "true");
  for (std::size_t k = 0; k < r.theta.size(); ++k) {
    fmt::print("  {:<4}{:>11.4f}{:>10.4f}{:>11.4f}{:>11.4f}\n", k + 1, r.theta[k], r.theta_std_error[k],
               paper_theta[k], truth[k]);
  }
  fmt::print("  ||ours - true|| / ||true|| = {:.4f}; ||paper - true|| / ||true|| = {:.4f}\n",
             relative_difference(r.theta, truth), relative_difference(paper_theta, truth));
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
  const Scenario& ais_s = find_scenario("ais_paper");
  ScenarioRun run;
  run.seed = args.seed;

  // --- DIS, Section 3.5 -------------------------------------------------------------------------------------
  const SchemeResult dis = identify_scenario(dis_s, est::Scheme::kDescending, run);
  const auto dis_truth = true_theta(dis_s.config, est::Scheme::kDescending);
  fmt::print("== DIS, paper Section 3.5: {} (seed {}) ==\n", dis_s.description, args.seed);
  print_scheme_result(dis_s.config, dis);
  fmt::print("  ybar0: ours {:.3f}, paper {:.2f}, true {:.3f}\n", dis.ybar0, paper::kDisYbar0,
             *dis_s.config.truth->ybar0_d);
  fmt::print("  Theta^d, paper (3.33):\n");
  print_theta(dis, paper::kDisTheta, dis_truth);
  fmt::print("  Table 1: a = ({:.4f}, {:.4f}) paper ({}, {});  b = ({:.3f}, {:.3f}) paper ({}, {})\n", dis.a[0],
             dis.a[1], paper::kDisTable1A[0], paper::kDisTable1A[1], dis.b[0], dis.b[1], paper::kDisTable1B[0],
             paper::kDisTable1B[1]);
  print_points("Table 2: F^d(V_j)", dis_s.config.V_d, dis_s.config.truth->F_d, paper::kDisTable2True, dis.F,
               paper::kDisTable2Estimate);
  out["dis"] = to_json(dis);

  // --- AIS, Section 4.2 -------------------------------------------------------------------------------------
  const SchemeResult ais = identify_scenario(ais_s, est::Scheme::kAscending, run);
  const auto ais_truth = true_theta(ais_s.config, est::Scheme::kAscending);
  fmt::print("\n== AIS, paper Section 4.2: {} (seed {}) ==\n", ais_s.description, args.seed);
  print_scheme_result(ais_s.config, ais);
  fmt::print("  ybar0: ours {:.3f}, paper {:.2f}, true {:.3f}\n", ais.ybar0, paper::kAisYbar0,
             *ais_s.config.truth->ybar0_a);
  fmt::print("  Theta^a, paper Section 4.2:\n");
  print_theta(ais, paper::kAisTheta, ais_truth);
  fmt::print("  Table 4: a = ({:.4f}, {:.4f}) paper ({}, {});  b = ({:.4f}, {:.4f}) paper ({}, {})\n", ais.a[0],
             ais.a[1], paper::kAisTable4A[0], paper::kAisTable4A[1], ais.b[0], ais.b[1], paper::kAisTable4B[0],
             paper::kAisTable4B[1]);
  print_points("Table 5: F^a(V_j)", ais_s.config.V_a, ais_s.config.truth->F_a, paper::kAisTable5True, ais.F,
               paper::kAisTable5Estimate);
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
    int first100 = 0;
    for (std::size_t r = 0; r < mc.relative_errors.size() && r < 100; ++r) first100 += mc.relative_errors[r] < mc.eps;
    fmt::print("  N = {:>5}: P = {:.3f} (first 100 runs: {:.2f}), mean relative error {:.4f}, {} failed runs\n", N,
               mc.probability, first100 / 100.0, mc.mean_relative_error, mc.failures);
    out["consistency"].push_back(summary_json(mc));
  }
  fmt::print("  paper, N = 2000: P = {} (100 runs), {} (1000 runs)\n", paper::kDisConsistencyP100,
             paper::kDisConsistencyP1000);

  // --- float32 (the firmware's precision) vs double ---------------------------------------------------------
  ScenarioRun f32 = run;
  f32.precision = Precision::kFloat;
  const double dis_f = relative_difference(identify_scenario(dis_s, est::Scheme::kDescending, f32).theta, dis.theta);
  const double ais_f = relative_difference(identify_scenario(ais_s, est::Scheme::kAscending, f32).theta, ais.theta);
  fmt::print("\n== float32 recursive estimate vs double: ||dTheta|| / ||Theta|| = {:.2g} (DIS), {:.2g} (AIS) ==\n",
             dis_f, ais_f);
  out["float32_relative_difference"] = {{"dis", dis_f}, {"ais", ais_f}};

  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  fmt::print("\nreproduce finished in {:.1f} s\n", seconds);
  if (!args.json_out.empty()) write_json_file(args.json_out, out);
  return dis.status == est::Status::kOk && ais.status == est::Status::kOk ? 0 : 2;
}

}  // namespace lashid::app
