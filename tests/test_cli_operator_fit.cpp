// End-to-end tests of `lashid operator-fit` (LASHID_EXE) on the measured damper data (LASHID_DAMPER_DATA): what
// it writes, its errors, and that a failing run leaves no file behind.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "json_text.hpp"

#include "cli_harness.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace lashid::test;

const std::string kData = LASHID_DAMPER_DATA;
const std::string kTrain = kData + "/char_0.25Hz30lbtension1amplitude.csv";
const std::string kTest1 = kData + "/char_1Hz30lbtension0.5amplitude.csv";
const std::string kTest2 = kData + "/eq_KocaeliDBE.csv";

class OperatorFitCli : public LashidExeTest {};

TEST_F(OperatorFitCli, WritesTheFitsOfBothModelsPerTestFile) {
  const Outcome r = run({"operator-fit", "--decimate", "8", "--train", kTrain, "--test", kTest1, kTest2, "--json",
                         "fit.json"});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(Contains(r.out, "error by phase of the loop"));
  EXPECT_TRUE(Contains(r.out, "% of the squared error is in the"));
  const json j = parse_json(slurp(work_ / "fit.json"));
  EXPECT_TRUE(j["nominal"]["operator"] == "switch" || j["nominal"]["operator"] == "backlash");
  EXPECT_EQ(j["extended"]["model"]["operator"], "friction_gap");
  EXPECT_GT(j["extended"]["model"]["half_width"].get<double>(), 0.0);
  for (const auto& file : {kTest1, kTest2}) {
    const double nominal = j["nominal"]["fit_test"][file].get<double>();
    const double extended = j["extended"]["fit_test"][file].get<double>();
    EXPECT_GT(extended, nominal) << file;
  }
  ASSERT_TRUE(j["cause"].is_array());
  ASSERT_FALSE(j["cause"].empty());
  EXPECT_EQ(j["cause"][0]["name"], "finite_stiffness_at_reversal");
  EXPECT_EQ(j["identification"]["dis"]["a"].size(), 2U);
  EXPECT_EQ(j["options"]["decimate"], 8);
}

// The dynamics after the operator: a filter of an order in 2..4 chosen on the single training file (its halves),
// its poles with their meaning at the decimated rate 1024 / 8 = 128 Hz (Nyquist 64 Hz), and the three fits per test
// file.
TEST_F(OperatorFitCli, ReportsTheDynamicsAfterTheOperatorPerTestFile) {
  const Outcome r = run({"operator-fit", "--decimate", "8", "--train", kTrain, "--test", kTest1, kTest2, "--json",
                         "fit.json"});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(Contains(r.out, "extended + dynamics"));
  const json j = parse_json(slurp(work_ / "fit.json"));
  const json& model = j["dynamics"]["model"];
  const int order = model["order"].get<int>();
  EXPECT_GE(order, 2);
  EXPECT_LE(order, 4);
  EXPECT_EQ(model["a"].size(), static_cast<std::size_t>(order));
  EXPECT_EQ(model["b"].size(), static_cast<std::size_t>(order) + 1);
  EXPECT_NEAR(model["sample_rate_hz"].get<double>(), 128.0, 1e-4);  // times in the files have 8 digits
  EXPECT_EQ(j["dynamics"]["order_selection"]["scores"].size(), 3U);
  ASSERT_EQ(model["poles"].size(), static_cast<std::size_t>(order));
  for (const auto& p : model["poles"]) {
    EXPECT_LT(p["magnitude"].get<double>(), 1.0);  // refined filters stay stable
    EXPECT_LE(p["natural_hz"].get<double>(), 64.0 * std::sqrt(2.0) + 1e-9);  // |ln z| <= sqrt(ln^2 r + pi^2)
  }
  for (const auto& file : {kTest1, kTest2}) {
    const json& fits = j["fit_test"][file];
    EXPECT_EQ(fits["extended"], j["extended"]["fit_test"][file]);
    EXPECT_EQ(fits["extended_dynamics"], j["dynamics"]["fit_test"][file]);
    EXPECT_TRUE(fits["extended_dynamics"].is_number()) << file;
    const json& oscillation = j["loop_analysis"][file]["extended_error_oscillation"];
    EXPECT_TRUE(oscillation["peak_hz"].is_number());
    // The displacement's echo is taken at the oscillation's peak, from the decimated record's 1 s windows.
    const json& echo = oscillation["displacement_echo"];
    EXPECT_EQ(echo["hz"], oscillation["peak_hz"]);
    EXPECT_GE(echo["coherence"].get<double>(), 0.0);
    EXPECT_LE(echo["coherence"].get<double>(), 1.0 + 1e-12);
    EXPECT_GE(echo["windows"].get<int>(), 2);
  }
  // The file whose error is most fast oscillation is one of the test files, and its words are those of its echo.
  const json& words = j["oscillation_in_words"];
  const std::string worst = words["file"].get<std::string>();
  EXPECT_TRUE(worst == kTest1 || worst == kTest2) << worst;
  EXPECT_EQ(words["text"], j["loop_analysis"][worst]["extended_error_oscillation"]["displacement_echo"]["text"]);
  EXPECT_TRUE(Contains(r.out, "what the final model misses most: on " + worst));
  EXPECT_TRUE(j["dynamics_in_words"]["named_as_cause"].is_boolean());
  EXPECT_TRUE(Contains(j["dynamics_in_words"]["text"].get<std::string>(), "identified on the training files only"));
}

// Training at 30 and 36 lb: the operator per band tension, each test file at its own tension (from its name, or
// --tension for the earthquake record, whose name has none).
TEST_F(OperatorFitCli, FitsTheOperatorPerBandTension) {
  const std::string train36 = kData + "/char_1Hz36lbtension1.5amplitude.csv";
  const Outcome r = run({"operator-fit", "--decimate", "16", "--train", kTrain, train36, "--test", kTest1, kTest2,
                         "--tension", "eq_KocaeliDBE.csv=36", "--json", "fit.json"});
  ASSERT_EQ(r.exit_code, 0) << r;
  const json j = parse_json(slurp(work_ / "fit.json"));
  EXPECT_EQ(j["tension_lb"]["train"], json({30.0, 36.0}));
  EXPECT_EQ(j["tension_lb"]["test"], json({30.0, 36.0}));
  const json& tensions = j["extended_tension"]["model"]["tensions"];
  ASSERT_EQ(tensions.size(), 2U);
  EXPECT_EQ(tensions[0]["tension_lb"], 30.0);
  EXPECT_EQ(tensions[1]["tension_lb"], 36.0);
  for (const auto& file : {kTest1, kTest2}) {
    EXPECT_EQ(j["fit_test"][file]["extended_tension"], j["extended_tension"]["fit_test"][file]);
  }
  // The profiles over each test file's unknowns: 41 initial offsets, and tensions 24..42 lb (one training span
  // beyond each end) by 1 lb. The file's own tension is on that grid and is the final model as run.
  const std::vector<double> own{30.0, 36.0};
  for (std::size_t i = 0; i < 2; ++i) {
    const std::string file = i == 0 ? kTest1 : kTest2;
    const json& profiles = j["test_profiles"][file];
    EXPECT_EQ(profiles["initial_offset"]["points"].size(), 41U) << file;
    const json& tension = profiles["tension"];
    ASSERT_EQ(tension["points"].size(), 19U) << file;
    EXPECT_EQ(tension["points"][0][0], 24.0);
    EXPECT_EQ(tension["points"][18][0], 42.0);
    const double as_run = j["fit_test"][file]["extended_dynamics"].get<double>();
    const auto at_own = static_cast<std::size_t>(own[i] - 24.0);
    EXPECT_DOUBLE_EQ(tension["points"][at_own][1].get<double>(), as_run) << file;
    EXPECT_GE(tension["best_fit"].get<double>(), as_run) << file;
  }
  EXPECT_TRUE(Contains(j["tension_in_words"]["text"].get<std::string>(), "scales with band tension"));
}

TEST_F(OperatorFitCli, MissingOrBadTensionNamesTheFileAndWritesNothing) {
  const std::string train36 = kData + "/char_1Hz36lbtension1.5amplitude.csv";
  const Outcome missing = run({"operator-fit", "--decimate", "16", "--train", kTrain, train36, "--test", kTest1,
                               kTest2, "--json", "fit.json"});
  EXPECT_EQ(missing.exit_code, 1) << missing;
  EXPECT_TRUE(Contains(missing.err, "eq_KocaeliDBE.csv: band tension unknown")) << missing;
  EXPECT_TRUE(Contains(missing.err, "--tension eq_KocaeliDBE.csv=LB")) << missing;
  const Outcome unknown = run({"operator-fit", "--decimate", "16", "--train", kTrain, "--test", kTest1,
                               "--tension", "other.csv=36"});
  EXPECT_EQ(unknown.exit_code, 1) << unknown;
  EXPECT_TRUE(Contains(unknown.err, "--tension 'other.csv=36': no --train or --test file is named 'other.csv'"));
  const Outcome bad = run({"operator-fit", "--decimate", "16", "--train", kTrain, "--test", kTest1, "--tension",
                           "eq_KocaeliDBE.csv=heavy"});
  EXPECT_EQ(bad.exit_code, 1) << bad;
  EXPECT_TRUE(Contains(bad.err, "'heavy' is not a band tension in lb"));
  EXPECT_TRUE(files_below(work_).empty());
}

TEST_F(OperatorFitCli, BadDataNamesFileLineAndColumnAndWritesNothing) {
  std::ofstream(work_ / "bad.csv") << "t_s,x_in,F_kip\n0,0,0\n0.1,nan,0\n";
  const Outcome r = run({"operator-fit", "--train", "bad.csv", "--test", kTest1, "--json", "fit.json"});
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(Contains(r.err, "bad.csv:3: column 'x_in': 'nan' is not finite"));
  EXPECT_EQ(files_below(work_), (std::set<std::string>{"bad.csv"}));

  std::ofstream(work_ / "nocol.csv") << "t_s,x,F_kip\n0,0,0\n";
  const Outcome missing = run({"operator-fit", "--train", kTrain, "--test", "nocol.csv"});
  EXPECT_EQ(missing.exit_code, 1) << missing;
  EXPECT_TRUE(Contains(missing.err, "nocol.csv:1: no column 'x_in'"));
}

// Issue 14 section 6: x_in near +1e308 and -1e308 (a span of inf) was undefined behaviour in the bin index of the
// borders. Now a clear error naming the file, line and column, a non-zero exit, and no file written; as a training
// file and as a test file.
TEST_F(OperatorFitCli, DisplacementSpanningMoreThanTheDoubleRangeNamesTheFileAndWritesNothing) {
  std::ofstream(work_ / "huge.csv") << "t_s,x_in,F_kip\n0,1e308,0\n0.001,-1e308,1\n0.002,1e308,-1\n";
  for (const auto& role : {"--train", "--test"}) {
    const std::vector<std::string> files = std::string(role) == "--train"
                                               ? std::vector<std::string>{"--train", "huge.csv", "--test", kTest1}
                                               : std::vector<std::string>{"--train", kTrain, "--test", "huge.csv"};
    std::vector<std::string> args{"operator-fit"};
    args.insert(args.end(), files.begin(), files.end());
    args.insert(args.end(), {"--json", "fit.json", "--plot", "fit.png"});
    const Outcome r = run(args);
    EXPECT_NE(r.exit_code, 0) << r;
    EXPECT_TRUE(Contains(r.err, "huge.csv:2: column 'x_in': 1e+308 is beyond 1e+12 in magnitude")) << r;
    EXPECT_TRUE(Contains(r.err, "not a displacement in inches")) << r;
    EXPECT_EQ(files_below(work_), (std::set<std::string>{"huge.csv"})) << role;
  }
}

TEST_F(OperatorFitCli, MissingGnuplotIsAClearErrorAndNothingIsWritten) {
  const Outcome r = run({"operator-fit", "--decimate", "16", "--train", kTrain, "--test", kTest1, "--json",
                         "fit.json", "--plot", "loops.png", "--gnuplot", "/nonexistent/gnuplot"});
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(Contains(r.err, "loops.png: cannot plot: '/nonexistent/gnuplot' not found (install gnuplot-nox)"));
  EXPECT_TRUE(files_below(work_).empty());
}

TEST_F(OperatorFitCli, PlotsTheLoopsAsPng) {
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) GTEST_SKIP() << "gnuplot is not installed";
  const Outcome r = run({"operator-fit", "--decimate", "16", "--train", kTrain, "--test", kTest1, "--plot",
                         "loops.png"});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_EQ(slurp(work_ / "loops.png").substr(0, 4), "\x89PNG");
  EXPECT_EQ(files_below(work_), (std::set<std::string>{"loops.png"}));
}

TEST_F(OperatorFitCli, RejectsBadOptions) {
  // Refused by the command line (CLI11's codes, 100 and above; README), naming the option at fault.
  const std::vector<std::pair<std::vector<std::string>, std::string>> wrong{
      {{"operator-fit", "--train", kTrain}, "--test is required"},
      {{"operator-fit", "--train", kTrain, "--test", kTest1, "--decimate", "0"}, "--decimate: Value 0 not in range"},
      {{"operator-fit", "--train", "missing.csv", "--test", kTest1}, "--train: File does not exist: missing.csv"},
  };
  for (const auto& [args, message] : wrong) {
    const Outcome r = run(args);
    EXPECT_GE(r.exit_code, 100) << r;
    EXPECT_TRUE(Contains(r.err, message)) << r;
  }
  const Outcome help = run({"operator-fit", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_TRUE(Contains(help.out, "--decimate"));
}

}  // namespace
