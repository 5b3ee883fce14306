// `lashid hil --record`: the phase of each sample of a firmware run (computed by hand from the design), the
// recorder's handling of retries, gaps and early stops, and a recording of the firmware on the in-process board
// that `lashid identify --float` reads and turns into the firmware's own on-device estimates.
#include <unistd.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "json_text.hpp"

#include "lashid/firmware/sequencer.hpp"
#include "lashid/hil/hil.hpp"
#include "lashid/hil/run_recording.hpp"
#include "lashid/io/json.hpp"
#include "lashid/io/plant_file.hpp"
#include "lashid/sim/file_plant.hpp"

namespace lashid::sim {
namespace {

namespace fs = std::filesystem;
using Part = RunSamplePlace::Part;

// n = 2, m = 6: T = max(n, 2) (m + 3) = 18, so the interval check of a backlash run is 16 T = 288 samples.
fw::RunDesign small_design(fw::OperatorKind op) {
  fw::RunDesign d;
  d.op = op;
  d.n = 2;
  d.m = 6;
  d.step_length = 10;     // step phases of 11 samples
  d.pulse_length_d = 40;
  d.pulse_length_a = 50;
  d.val_length = 7;
  return d;
}

TEST(RunPhases, BacklashRunSkipsTheIntervalCheckThenFollowsTheFivePhases) {
  const fw::RunDesign d = small_design(fw::OperatorKind::kBacklash);
  EXPECT_EQ(d.interval_check_samples(), 288U);  // 4 periods of 2 x 2T, T = 18
  EXPECT_EQ(recorded_samples(d), 11U + 40U + 11U + 50U + 7U);
  const auto at = [&](std::uint64_t k) { return place_of_sample(d, k); };
  EXPECT_EQ(at(0), (RunSamplePlace{Part::kIntervalCheck, Phase::kStepD, 0}));
  EXPECT_EQ(at(287), (RunSamplePlace{Part::kIntervalCheck, Phase::kStepD, 287}));
  EXPECT_EQ(at(288), (RunSamplePlace{Part::kPhase, Phase::kStepD, 0}));
  EXPECT_EQ(at(298), (RunSamplePlace{Part::kPhase, Phase::kStepD, 10}));
  EXPECT_EQ(at(299), (RunSamplePlace{Part::kPhase, Phase::kDis, 0}));
  EXPECT_EQ(at(338), (RunSamplePlace{Part::kPhase, Phase::kDis, 39}));
  EXPECT_EQ(at(339), (RunSamplePlace{Part::kPhase, Phase::kStepA, 0}));
  EXPECT_EQ(at(350), (RunSamplePlace{Part::kPhase, Phase::kAis, 0}));
  EXPECT_EQ(at(399), (RunSamplePlace{Part::kPhase, Phase::kAis, 49}));
  EXPECT_EQ(at(400), (RunSamplePlace{Part::kPhase, Phase::kVal, 0}));
  EXPECT_EQ(at(406), (RunSamplePlace{Part::kPhase, Phase::kVal, 6}));
  EXPECT_EQ(at(407), (RunSamplePlace{Part::kAfterRun, Phase::kVal, 0}));
}

TEST(RunPhases, SwitchRunStartsWithTheDisStep) {
  const fw::RunDesign d = small_design(fw::OperatorKind::kSwitch);
  EXPECT_EQ(d.interval_check_samples(), 0U);
  EXPECT_EQ(place_of_sample(d, 0), (RunSamplePlace{Part::kPhase, Phase::kStepD, 0}));
  EXPECT_EQ(place_of_sample(d, 11), (RunSamplePlace{Part::kPhase, Phase::kDis, 0}));
  EXPECT_EQ(place_of_sample(d, 118), (RunSamplePlace{Part::kPhase, Phase::kVal, 6}));
  EXPECT_EQ(place_of_sample(d, 119).part, Part::kAfterRun);
}

class RecorderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // The pid in the name: the host-release, host-asan and host-hil trees may run this test at the same time.
    dir_ = fs::temp_directory_path() / ("lashid_test_record_" + std::to_string(::getpid()) + "_" +
                                        std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }
  static std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  fs::path dir_;
};

TEST_F(RecorderTest, RetriesAreRecordedOnceAndTheIntervalCheckNotAtAll) {
  const fw::RunDesign d = small_design(fw::OperatorKind::kBacklash);
  const fs::path path = dir_ / "rec.csv";
  RunRecorder recorder(path, d, {"test run"});
  for (std::uint64_t t = 0; t < 407; ++t) {
    const auto v = static_cast<float>(t);
    recorder.sample(t, v, -v);
    recorder.sample(t, v + 0.5f, 99.0f);  // a retry of the same t: the host answers from its cache
  }
  EXPECT_TRUE(recorder.complete());
  recorder.finish("done");
  const Recording rec = read_recording_csv(path);
  EXPECT_EQ(rec.phase(Phase::kStepD).size(), 11U);
  EXPECT_EQ(rec.phase(Phase::kDis).size(), 40U);
  EXPECT_EQ(rec.phase(Phase::kStepA).size(), 11U);
  EXPECT_EQ(rec.phase(Phase::kAis).size(), 50U);
  EXPECT_EQ(rec.phase(Phase::kVal).size(), 7U);
  // Sample k of the run carries v = k: step_d starts after the 288 interval-check samples.
  EXPECT_EQ(rec.phase(Phase::kStepD)[0], (Sample{288, -288}));
  EXPECT_EQ(rec.phase(Phase::kDis)[0], (Sample{299, -299}));
  EXPECT_EQ(rec.phase(Phase::kVal)[6], (Sample{406, -406}));
  EXPECT_EQ(slurp(path).find("partial"), std::string::npos);
  EXPECT_EQ(slurp(path).rfind("# test run\n", 0), 0U);
}

TEST_F(RecorderTest, AnEarlyStopKeepsWhatWasMeasuredAndSaysItIsPartial) {
  const fw::RunDesign d = small_design(fw::OperatorKind::kSwitch);
  const fs::path path = dir_ / "rec.csv";
  RunRecorder recorder(path, d, {});
  for (std::uint64_t t = 0; t < 20; ++t) recorder.sample(t, 1.0f, 2.0f);  // step_d (11) and 9 of dis
  EXPECT_FALSE(recorder.complete());
  recorder.finish("the firmware ended with status 'sensor fault'");
  const Recording rec = read_recording_csv(path);
  EXPECT_EQ(rec.phase(Phase::kStepD).size(), 11U);
  EXPECT_EQ(rec.phase(Phase::kDis).size(), 9U);
  EXPECT_NE(slurp(path).find("# partial recording: the firmware ended with status 'sensor fault'; 20 of the "
                             "design's 119 samples were measured"),
            std::string::npos)
      << slurp(path);
}

TEST_F(RecorderTest, NothingAfterAGapAndNoFileWithoutASample) {
  const fw::RunDesign d = small_design(fw::OperatorKind::kSwitch);
  RunRecorder gap(dir_ / "gap.csv", d, {});
  gap.sample(0, 1.0f, 1.0f);
  gap.sample(2, 1.0f, 1.0f);  // t = 1 never came
  gap.sample(3, 1.0f, 1.0f);
  gap.finish("stopped");
  EXPECT_EQ(read_recording_csv(dir_ / "gap.csv").size(), 1U);
  EXPECT_NE(slurp(dir_ / "gap.csv").find("sample t = 1 of the run never arrived"), std::string::npos);

  RunRecorder empty(dir_ / "empty.csv", d, {});
  EXPECT_THROW(empty.finish("stopped"), DataError);
  EXPECT_FALSE(fs::exists(dir_ / "empty.csv"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1) << "no temporary left";
}

TEST_F(RecorderTest, TheFileGrowsWhileTheRunGoesOn) {
  const fw::RunDesign d = small_design(fw::OperatorKind::kSwitch);
  RunRecorder recorder(dir_ / "rec.csv", d, {});
  for (std::uint64_t t = 0; t < 12; ++t) recorder.sample(t, 1.0f, 2.0f);  // into dis: step_d was flushed
  fs::path temporary;
  for (const auto& entry : fs::directory_iterator(dir_)) temporary = entry.path();
  ASSERT_TRUE(temporary.filename().string().starts_with(".rec.csv.tmp-")) << temporary;
  EXPECT_NE(slurp(temporary).find("step_d,10,1,2\n"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir_ / "rec.csv"));
  recorder.discard();
  EXPECT_FALSE(fs::exists(temporary));
}

double relative_difference(const std::vector<double>& x, const std::vector<float>& ref) {
  double num = 0, den = 0;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    const auto r = static_cast<double>(ref[k]);
    num += (x.at(k) - r) * (x.at(k) - r);
    den += r * r;
  }
  return std::sqrt(num / den);
}

// The in-process board runs the dis_paper image's firmware (backlash: the 288-sample interval check first).
TEST_F(RecorderTest, AHostBoardRecordingIdentifiesToTheFirmwaresOwnEstimates) {
  HilOptions options;
  options.scenario = "dis_paper";
  options.seed = 3;
  options.record = (dir_ / "rec.csv").string();
  const HilResult r = run_on_host_board(options);
  ASSERT_EQ(r.done, static_cast<int>(fw::RunStatus::kOk));
  ASSERT_EQ(r.estimates.size(), 2U);
  EXPECT_TRUE(r.recording_complete);
  EXPECT_EQ(r.recorded, 2U * 2001U + 2000U + 2000U);
  EXPECT_EQ(r.samples, 288U + r.recorded);

  const Scenario& scenario = find_scenario("dis_paper");
  write_json_file(dir_ / "cfg.json", to_json(scenario.config));
  const std::string command = std::string("'") + LASHID_EXE + "' identify --float --config '" +
                              (dir_ / "cfg.json").string() + "' --data '" + (dir_ / "rec.csv").string() +
                              "' --json '" + (dir_ / "est.json").string() + "' > '" + (dir_ / "out.txt").string() +
                              "' 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << slurp(dir_ / "out.txt");
  const auto estimates = parse_json(slurp(dir_ / "est.json"));
  for (const fw::EstimateRecord& e : r.estimates) {
    const auto& cli = estimates.at(e.scheme == est::Scheme::kDescending ? "dis" : "ais");
    const std::vector<float> a(e.a.begin(), e.a.begin() + e.n), b(e.b.begin(), e.b.begin() + e.n);
    const std::vector<float> F(e.F.begin(), e.F.begin() + e.m);
    // The same float32 estimator on the same samples, compiled once: equal (0 measured). hil's 1e-3 is for an
    // image built by another compiler (QEMU: 2.3e-5); here 1e-6 would still catch one sample lost or repeated.
    EXPECT_LT(relative_difference(cli.at("a").get<std::vector<double>>(), a), 1e-6);
    EXPECT_LT(relative_difference(cli.at("b").get<std::vector<double>>(), b), 1e-6);
    EXPECT_LT(relative_difference(cli.at("F").get<std::vector<double>>(), F), 1e-6);
  }
}

// A plant file played to the firmware on the host board with a design that has a val phase, against
// `simulate --plant` of the same design and seed. A switch design runs no interval check, and its levels are exact
// in float32, so the firmware commands the same v and the plant answers the same y, which the link rounds to float:
// the two recordings agree sample for sample, val included (the device's generator on both sides).
TEST_F(RecorderTest, AFirmwareRecordingOfAPlantFileEqualsItsSimulation) {
  const fs::path plant_path = dir_ / "plant.json";
  std::ofstream(plant_path) << R"({"operator": "switch",
      "borders": {"v": [-2, 0, 2], "ascending": [-1.5, -0.5, 0.5], "descending": [-0.5, 0.7, 1.5]},
      "a": [-0.6], "b": [0.8], "equation_noise_std": 0.01, "sensor_noise": {"std": 0.02, "pole": 0.5},
      "dead_time": 1, "sensor_drift_per_sample": 1e-5})";
  ExperimentConfig config{};
  config.n = 1;
  config.m = 2;
  config.v_min = -2;
  config.v_max = 2;
  config.V_d = {-2, 0};
  config.V_a = {2, 0};
  config.op = OperatorKind::kSwitch;
  const fw::RunDesign design = to_run_design(
      config, {.step_length = 100, .pulse_length_d = 300, .pulse_length_a = 300, .val_length = 500, .val_seed = 9});

  HilOptions options;
  options.design = design;
  options.plant_file = plant_path.string();
  options.seed = 21;
  options.record = (dir_ / "hil.csv").string();
  const HilResult r = run_on_host_board(options);
  ASSERT_EQ(r.done, static_cast<int>(fw::RunStatus::kOk));
  EXPECT_TRUE(r.recording_complete);
  const Recording firmware = read_recording_csv(dir_ / "hil.csv");

  const Recording simulated = simulate_file_plant(read_plant_json(plant_path), "plant.json", config, design, 21);
  ASSERT_EQ(firmware.order(), simulated.order());
  ASSERT_EQ(firmware.order().size(), 5U);
  for (const Phase phase : simulated.order()) {
    const auto f = firmware.phase(phase);
    const auto s = simulated.phase(phase);
    ASSERT_EQ(f.size(), s.size()) << to_string(phase);
    for (std::size_t t = 0; t < s.size(); ++t) {
      ASSERT_EQ(f[t].v, s[t].v) << to_string(phase) << " t = " << t;
      ASSERT_EQ(f[t].y, static_cast<double>(static_cast<float>(s[t].y))) << to_string(phase) << " t = " << t;
    }
  }
}

}  // namespace
}  // namespace lashid::sim
