// `lashid diagnose` with several hidden causes, through the real executable: the JSON's "causes", "cause",
// "parameters" and "gain_per_cause" (issue 12). The single-cause and bad-input cases are in test_cli.cpp.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "json_text.hpp"

#include "cli_harness.hpp"
#include "sanitizer_budget.hpp"
#include "lashid/sim/hidden_effect.hpp"

namespace {

using nlohmann::json;
using namespace lashid::test;

class CliDiagnose : public LashidExeTest {};

// Every step of "gain_per_cause" carries its cause's parameters as the final model has them ("parameters"): the
// steps decompose the final model's gain (the last one ends at fit_extended).
void expect_steps_carry_the_final_parameters(const json& j) {
  for (const json& step : j.at("gain_per_cause")) {
    for (const auto& [key, value] : step.at("parameters").items()) {
      ASSERT_TRUE(j.at("parameters").contains(key)) << key;
      EXPECT_EQ(value, j.at("parameters").at(key)) << step.at("cause") << " " << key;
    }
  }
}

// Two effects hidden at once on curved borders: the JSON names both (strongest first in "causes", "cause" the
// first), gives both parameters, and one gain per cause added; a recording without effect gives ["none"].
TEST_F(CliDiagnose, NamesTwoHiddenCausesAndTheGainOfEach) {
  LASHID_SKIP_UNDER_SANITIZERS("Cli.DiagnoseFindsAHiddenDeadTimeAndWritesTheJson and "
                               "CliDiagnose.FindsAnInputLagBehindABacklashOnTheGridPoint");
  const std::string csv = (work_ / "pair.csv").string(), cfg = (work_ / "pair.json").string();
  const std::string out = (work_ / "diag.json").string();
  const Outcome gen = run({"hidden-effect", "--cause", "sensor_drift+colored_noise", "--borders", "curved", "--seed",
                           "11", "--out", csv, "--config-out", cfg});
  ASSERT_EQ(gen.exit_code, 0) << gen;
  const Outcome r = run({"diagnose", "--config", cfg, "--data", csv, "--json", out});
  ASSERT_EQ(r.exit_code, 0) << r;
  const json j = parse_json(slurp(out));
  std::vector<std::string> causes = j.at("causes").get<std::vector<std::string>>();
  ASSERT_FALSE(causes.empty());
  EXPECT_EQ(j.at("cause"), causes.front());
  std::sort(causes.begin(), causes.end());
  EXPECT_EQ(causes, (std::vector<std::string>{"colored_noise", "sensor_drift"})) << j.at("causes");
  // The drift the generator hid (the same case, drawn in-process), within the 20 % of issue 12's rule.
  const std::vector<lashid::sim::Cause> hidden{lashid::sim::Cause::kSensorDrift, lashid::sim::Cause::kColoredNoise};
  lashid::sim::HiddenEffectOptions curved;
  curved.borders = lashid::sim::BorderShape::kCurved;
  const double drift = lashid::sim::generate_hidden_effect_case(hidden, 11, curved).effect.drift_total;
  ASSERT_TRUE(j.at("parameters").contains("drift_total")) << j.at("parameters");
  EXPECT_NEAR(j.at("parameters").at("drift_total").get<double>(), drift, 0.2 * std::abs(drift));
  ASSERT_EQ(j.at("gain_per_cause").size(), 2U);
  // Each step starts where the previous one ended, from the nominal fit to the extended one.
  double fit = j.at("fit_nominal").get<double>();
  for (const json& step : j.at("gain_per_cause")) {
    EXPECT_DOUBLE_EQ(step.at("fit_before").get<double>(), fit);
    fit = step.at("fit_after").get<double>();
  }
  EXPECT_DOUBLE_EQ(fit, j.at("fit_extended").get<double>());
  expect_steps_carry_the_final_parameters(j);

  // An input lag added before a drift is searched again on top of it: before the fix the step said lambda 0.11
  // while the final model, whose fit the last step ends at, had 0.2 (input_lag+sensor_drift, curved, seed 5002).
  ASSERT_EQ(run({"hidden-effect", "--cause", "input_lag+sensor_drift", "--borders", "curved", "--seed", "5002",
                 "--out", csv, "--config-out", cfg})
                .exit_code,
            0);
  ASSERT_EQ(run({"diagnose", "--config", cfg, "--data", csv, "--json", out}).exit_code, 0);
  const json lag = parse_json(slurp(out));
  ASSERT_TRUE(lag.at("parameters").contains("lambda")) << lag.at("parameters");
  const json& steps = lag.at("gain_per_cause");
  const auto lag_step = std::find_if(steps.begin(), steps.end(), [](const json& s) { return s.at("cause") == "input_lag"; });
  ASSERT_NE(lag_step, steps.end()) << steps;
  ASSERT_TRUE(lag_step->at("parameters").contains("lambda")) << *lag_step;
  expect_steps_carry_the_final_parameters(lag);

  const Outcome none = run({"hidden-effect", "--cause", "none", "--borders", "curved", "--seed", "11", "--out", csv,
                            "--config-out", cfg});
  ASSERT_EQ(none.exit_code, 0) << none;
  ASSERT_EQ(run({"diagnose", "--config", cfg, "--data", csv, "--json", out}).exit_code, 0);
  const json k = parse_json(slurp(out));
  EXPECT_EQ(k.at("causes"), json::array({"none"}));
  EXPECT_EQ(k.at("cause"), "none");
  EXPECT_TRUE(k.at("gain_per_cause").empty());
  const Outcome unknown =
      run({"hidden-effect", "--cause", "dead_time+drift", "--seed", "1", "--out", csv, "--config-out", cfg});
  EXPECT_EQ(unknown.exit_code, 1) << unknown;
  EXPECT_TRUE(Contains(unknown.err, "--cause dead_time+drift: unknown cause 'drift'")) << unknown;
}

// The plant of tests/data/plants/backlash_dead_time.json with an input lag of 0.4 instead of its dead time, on a
// design from `lashid design`. With the lambda grid on the true 0.4, the border points the experiments reach for a
// sample or two took wild values, and the val simulation fell to -16 % (seed 2): the val check then rejected the
// lag and the answer was colored_noise. The truth is in the plant file.
TEST_F(CliDiagnose, FindsAnInputLagBehindABacklashOnTheGridPoint) {
  const json plant = {
      {"name", "backlash with a hidden input lag of 0.4"},
      {"operator", "backlash"},
      {"borders",
       {{"v", {-4.0, -3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0}},
        {"ascending",
         {-1.176116, -1.136167, -1.034068, -0.796844, -0.349575, 0.23685, 0.725241, 1.000386, 1.122491, 1.170892}},
        {"descending",
         {-1.122491, -1.000386, -0.725241, -0.23685, 0.349575, 0.796844, 1.034068, 1.136167, 1.176116, 1.191158}}}},
      {"a", {-1.3, 0.4}},
      {"b", {1.0, 0.5}},
      {"equation_noise_std", 0.02},
      {"input_lag", 0.4}};
  std::ofstream(work_ / "lag.json") << plant.dump();
  ASSERT_EQ(run({"design", "--n", "2", "--m", "6", "--v-min", "-3", "--v-max", "4", "--levels", "8", "--operator",
                 "backlash", "--val-length", "3000", "--out", "cfg.json"})
                .exit_code,
            0);
  ASSERT_EQ(run({"simulate", "--plant", "lag.json", "--config", "cfg.json", "--seed", "2", "--out", "rec.csv"})
                .exit_code,
            0);
  const Outcome r = run({"diagnose", "--config", "cfg.json", "--data", "rec.csv", "--json", "diag.json"});
  ASSERT_EQ(r.exit_code, 0) << r;
  const json j = parse_json(slurp(work_ / "diag.json"));
  EXPECT_EQ(j.at("causes"), json::array({"input_lag"}));
  EXPECT_NEAR(j.at("parameters").at("lambda").get<double>(), 0.4, 0.05);
  EXPECT_GT(j.at("fit_extended").get<double>(), j.at("fit_nominal").get<double>() + 10.0);
}

// diagnose-sweep --row runs only the named rows; a name that is not a row of the chosen table is an error that
// lists the table's rows (a pair needs --pairs).
TEST_F(CliDiagnose, SweepRunsOnlyTheNamedRowAndRefusesAnUnknownOne) {
  const Outcome one = run({"diagnose-sweep", "--row", "none", "--seeds", "1", "--first-seed", "5000"});
  ASSERT_EQ(one.exit_code, 0) << one;
  EXPECT_NE(one.out.find("none "), std::string::npos) << one;
  EXPECT_EQ(one.out.find("dead_time "), std::string::npos) << one;
  EXPECT_NE(one.out.find("1 of 1 hits"), std::string::npos) << one;
  const Outcome pair = run({"diagnose-sweep", "--row", "input_lag+sensor_drift", "--seeds", "1"});
  EXPECT_EQ(pair.exit_code, 1) << pair;
  EXPECT_NE(pair.err.find("lashid: error: --row"), std::string::npos) << pair;
  EXPECT_NE(pair.err.find("not a row of this table"), std::string::npos) << pair;
  EXPECT_NE(pair.err.find("pairs need --pairs"), std::string::npos) << pair;
}

// diagnose-sweep --oracle: for an input lag (only the equation error disturbs it) the generator's plant on the
// true-structure fit's tables predicts to the noise level (closed form: one-step error = rows x noise variance, so
// about 1 with linear borders, which the tables hold exactly). One case: a diagnosis and four more fits.
TEST_F(CliDiagnose, SweepOracleComparesTheTruePlantWithTheFit) {
  const Outcome r = run({"diagnose-sweep", "--row", "input_lag", "--seeds", "1", "--first-seed", "5360", "--oracle",
                         "--verbose", "--json", "sweep.json"});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_NE(r.out.find("oracle (one-step error"), std::string::npos) << r;
  const json j = parse_json(slurp(work_ / "sweep.json"));
  ASSERT_EQ(j.at("cases").size(), 1U);
  const json& lag = j.at("cases").at(0);
  EXPECT_NEAR(lag.at("oracle").at("truth").get<double>(), 1.0, 0.06);
  EXPECT_GT(lag.at("oracle").at("val_truth").get<double>(), 95.0);
  // Held to the true regimes, the fit takes its own regimes: its own error is at the noise level too.
  EXPECT_LT(lag.at("oracle").at("from_true_regimes_consistent").get<double>(), 1.3);
  // So does the fit with a regime search, which does not use the truth.
  EXPECT_LT(lag.at("oracle").at("regime_search").get<double>(), 1.3);
  EXPECT_NE(r.out.find("with a regime search"), std::string::npos) << r;
}

// diagnose-sweep --oracle-regimes (research): the input-lag search started from the generator's plant. Tuning seed
// 1099 (a backlash, true lambda 0.466, which the diagnosis alone answers 0.53): lambda within 0.05 of the
// generator's, and both the table and the JSON say that this is not a diagnosis.
TEST_F(CliDiagnose, SweepOracleRegimesStartsTheLagSearchFromTheTruePlant) {
  const Outcome r = run({"diagnose-sweep", "--row", "input_lag", "--borders", "curved", "--seeds", "1", "--first-seed",
                         "1099", "--oracle-regimes", "--json", "oracle_regimes.json"});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_NE(r.out.find("not a diagnosis"), std::string::npos) << r;
  const json j = parse_json(slurp(work_ / "oracle_regimes.json"));
  EXPECT_TRUE(j.at("oracle_regimes").get<bool>());
  ASSERT_EQ(j.at("cases").size(), 1U);
  const json& lag = j.at("cases").at(0);
  EXPECT_EQ(lag.at("truth").at("operator").get<std::string>(), "backlash");
  EXPECT_NEAR(lag.at("parameters").at("lambda").get<double>(), lag.at("truth").at("lambda").get<double>(), 0.05);
}

}  // namespace
