// `lashid diagnose` with several hidden causes, through the real executable: the JSON's "causes", "cause",
// "parameters" and "gain_per_cause" (issue 12). The single-cause and bad-input cases are in test_cli.cpp.
#include <algorithm>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

namespace {

using nlohmann::json;
using namespace lashid::test;

class CliDiagnose : public LashidExeTest {};

// Two effects hidden at once on curved borders: the JSON names both (strongest first in "causes", "cause" the
// first), gives both parameters, and one gain per cause added; a recording without effect gives ["none"].
TEST_F(CliDiagnose, NamesTwoHiddenCausesAndTheGainOfEach) {
  const std::string csv = (work_ / "pair.csv").string(), cfg = (work_ / "pair.json").string();
  const std::string out = (work_ / "diag.json").string();
  const Outcome gen = run({"hidden-effect", "--cause", "sensor_drift+colored_noise", "--borders", "curved", "--seed",
                           "11", "--out", csv, "--config-out", cfg});
  ASSERT_EQ(gen.exit_code, 0) << gen;
  const Outcome r = run({"diagnose", "--config", cfg, "--data", csv, "--json", out});
  ASSERT_EQ(r.exit_code, 0) << r;
  const json j = json::parse(slurp(out));
  std::vector<std::string> causes = j.at("causes").get<std::vector<std::string>>();
  ASSERT_FALSE(causes.empty());
  EXPECT_EQ(j.at("cause"), causes.front());
  std::sort(causes.begin(), causes.end());
  EXPECT_EQ(causes, (std::vector<std::string>{"colored_noise", "sensor_drift"})) << j.at("causes");
  EXPECT_TRUE(j.at("parameters").contains("drift_total")) << j.at("parameters");
  ASSERT_EQ(j.at("gain_per_cause").size(), 2U);
  // Each step starts where the previous one ended, from the nominal fit to the extended one.
  double fit = j.at("fit_nominal").get<double>();
  for (const json& step : j.at("gain_per_cause")) {
    EXPECT_DOUBLE_EQ(step.at("fit_before").get<double>(), fit);
    fit = step.at("fit_after").get<double>();
  }
  EXPECT_DOUBLE_EQ(fit, j.at("fit_extended").get<double>());

  const Outcome none = run({"hidden-effect", "--cause", "none", "--borders", "curved", "--seed", "11", "--out", csv,
                            "--config-out", cfg});
  ASSERT_EQ(none.exit_code, 0) << none;
  ASSERT_EQ(run({"diagnose", "--config", cfg, "--data", csv, "--json", out}).exit_code, 0);
  const json k = json::parse(slurp(out));
  EXPECT_EQ(k.at("causes"), json::array({"none"}));
  EXPECT_EQ(k.at("cause"), "none");
  EXPECT_TRUE(k.at("gain_per_cause").empty());
  EXPECT_NE(run({"hidden-effect", "--cause", "dead_time+drift", "--seed", "1", "--out", csv, "--config-out", cfg})
                .exit_code,
            0);
}

}  // namespace
