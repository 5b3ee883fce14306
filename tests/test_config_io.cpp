// Experiment config JSON: validation errors name file, key and index; writing round-trips exactly; a
// recording is checked against the config it is used with.
#include <unistd.h>

#include <array>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "json_text.hpp"
#include "lashid/io/config.hpp"
#include "lashid/io/json.hpp"

#include "data_error_matchers.hpp"

namespace lashid::sim {
namespace config_io_test {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr std::string_view kSource = "cfg.json";

using test::Contains;
using test::error_of;


// The example of docs/data-format.md.
json valid_document() {
  return parse_json(R"({"n": 2, "m": 6, "v_min": -3, "v_max": 4,
                         "V_d": [-3, -2, -1, 0, 1, 2], "V_a": [4, 3, 2, 1, 0, -1], "operator": "backlash"})");
}

std::string config_error(const json& document) {
  return error_of([&] { parse_config_json(document.dump(), kSource); });
}

// `document` with `key` set to `value` (a JSON pointer like "/V_d/2" reaches into arrays).
json with(json document, const std::string& pointer, json value) {
  document[json::json_pointer(pointer)] = std::move(value);
  return document;
}

json without(json document, const std::string& key) {
  document.erase(key);
  return document;
}

TEST(ConfigParse, ReadsTheDocumentedExample) {
  const ExperimentConfig config = parse_config_json(valid_document().dump(), kSource);
  EXPECT_EQ(config.n, 2);
  EXPECT_EQ(config.m, 6);
  EXPECT_EQ(config.v_min, -3.0);
  EXPECT_EQ(config.v_max, 4.0);
  EXPECT_EQ(config.V_d, (std::vector<double>{-3, -2, -1, 0, 1, 2}));
  EXPECT_EQ(config.V_a, (std::vector<double>{4, 3, 2, 1, 0, -1}));
  EXPECT_EQ(config.op, OperatorKind::kBacklash);
  EXPECT_FALSE(config.truth);
}

TEST(ConfigParse, SchemesAndTruthFieldsAreOptional) {
  const ExperimentConfig dis_only =
      parse_config_json(with(without(valid_document(), "V_a"), "/operator", "switch").dump(), kSource);
  EXPECT_TRUE(dis_only.V_a.empty());
  EXPECT_EQ(dis_only.op, OperatorKind::kSwitch);
  EXPECT_NO_THROW(parse_config_json(without(without(valid_document(), "V_a"), "V_d").dump(), kSource));

  const ExperimentConfig empty_truth =
      parse_config_json(with(valid_document(), "/truth", json::object()).dump(), kSource);
  ASSERT_TRUE(empty_truth.truth);
  EXPECT_EQ(*empty_truth.truth, Truth{});

  const ExperimentConfig some_truth =
      parse_config_json(with(valid_document(), "/truth", {{"a", {-1.2, 0.35}}, {"ybar0_a", 26.37}}).dump(), kSource);
  ASSERT_TRUE(some_truth.truth);
  EXPECT_EQ(some_truth.truth->a, (std::vector<double>{-1.2, 0.35}));
  EXPECT_TRUE(some_truth.truth->b.empty());
  EXPECT_EQ(some_truth.truth->ybar0_a, 26.37);
  EXPECT_FALSE(some_truth.truth->ybar0_d);
}

TEST(ConfigParse, RejectsInvalidJsonWithLine) {
  EXPECT_TRUE(Contains(error_of([] { parse_config_json("{\n  \"n\": 2,\n  \"m\": ,\n}", kSource); }),
                       "cfg.json:3: invalid JSON: parse error at line 3"));
  EXPECT_TRUE(Contains(error_of([] { parse_config_json("", kSource); }), "cfg.json:1: invalid JSON"));
  EXPECT_TRUE(Contains(error_of([] { parse_config_json(R"({"n": 2, "v_min": 1e999})", kSource); }),
                       "cfg.json: invalid JSON: number overflow parsing '1e999' "
                       "(at key 'v_min')"));
  EXPECT_TRUE(Contains(config_error(json::array()), "cfg.json: the top level must be a JSON object, got array"));
}

TEST(ConfigParse, RejectsUnknownAndDuplicateKeys) {
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "/v_mx", 1)), "cfg.json: unknown key 'v_mx' (allowed: n,"));
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "/truth", {{"c", 1}})), "unknown key 'truth.c'"));
  EXPECT_TRUE(Contains(error_of([] { parse_config_json(R"({"n": 2, "m": 6, "n": 3})", kSource); }),
                       "cfg.json: duplicate key 'n'"));
  EXPECT_TRUE(Contains(error_of([] { parse_config_json(R"({"truth": {"a": [1], "a": [2]}})", kSource); }),
                       "cfg.json: duplicate key 'truth.a'"));
}

TEST(ConfigParse, RejectsMissingRequiredKeys) {
  for (const std::string key : {"n", "m", "v_min", "v_max", "operator"}) {
    EXPECT_TRUE(Contains(config_error(without(valid_document(), key)),
                         fmt::format("cfg.json: missing required key '{}'", key)));
  }
}

TEST(ConfigParse, RejectsSizesOutsideTheCompiledRange) {
  EXPECT_TRUE(
      Contains(config_error(with(valid_document(), "/n", kMinOrder - 1)),
               fmt::format("'n' = {} is outside the compiled range [{}, {}]", kMinOrder - 1, kMinOrder, kMaxOrder)));
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "/n", kMaxOrder + 1)), "'n' = 5 is outside"));
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "/m", kMaxPoints + 1)), "'m' = 11 is outside"));
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "/m", 0)), "'m' = 0 is outside"));
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "/n", 2.0)), "'n' must be an integer, got 2.0"));
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "/n", "2")), "'n' must be an integer, got \"2\""));
  // Quoted as the file has it (a clamped 4294967296 was quoted before).
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "/m", 18446744073709551615ULL)),
                       "'m' = 18446744073709551615 is outside"));
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "/m", 9223372036854775808ULL)),
                       "'m' = 9223372036854775808 is outside"));
}

TEST(ConfigParse, RejectsBadWorkingInterval) {
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "/v_min", "low")), "'v_min' must be a number"));
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "/v_max", -3)),
                       "cfg.json: 'v_max' = -3 must be greater than 'v_min' = -3"));
}

TEST(ConfigParse, RejectsBadOperator) {
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "/operator", "Backlash")),
                       "'operator' must be \"switch\" or \"backlash\", got \"Backlash\""));
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "/operator", 1)), "'operator' must be"));
}

TEST(ConfigParse, RejectsBadDescendentLevels) {
  const json base = valid_document();
  EXPECT_TRUE(Contains(config_error(with(base, "/V_d", 3)), "'V_d' must be an array of m = 6 numbers, got number"));
  EXPECT_TRUE(Contains(config_error(with(base, "/V_d", {-3, -2, -1, 0, 1})), "'V_d' must have m = 6 entries, got 5"));
  EXPECT_TRUE(Contains(config_error(with(base, "/V_d/2", "x")), "'V_d[2]' must be a number"));
  EXPECT_TRUE(Contains(config_error(with(base, "/V_d/0", -2.5)), "'V_d[0]' = -2.5 must equal 'v_min' = -3"));
  EXPECT_TRUE(Contains(config_error(with(base, "/V_d/3", -1)),
                       "'V_d[3]' = -1 must be greater than 'V_d[2]' = -1 (V_d is strictly increasing)"));
  EXPECT_TRUE(Contains(config_error(with(base, "/V_d/5", 4)), "'V_d[5]' = 4 must be less than 'v_max' = 4"));
}

TEST(ConfigParse, RejectsBadAscendentLevels) {
  const json base = valid_document();
  EXPECT_TRUE(Contains(config_error(with(base, "/V_a", json::array())), "'V_a' must have m = 6 entries, got 0"));
  EXPECT_TRUE(Contains(config_error(with(base, "/V_a/4", nullptr)), "'V_a[4]' must be a number, got null"));
  EXPECT_TRUE(Contains(config_error(with(base, "/V_a/0", 3.5)), "'V_a[0]' = 3.5 must equal 'v_max' = 4"));
  EXPECT_TRUE(Contains(config_error(with(base, "/V_a/2", 3.5)),
                       "'V_a[2]' = 3.5 must be less than 'V_a[1]' = 3 (V_a is strictly decreasing)"));
  EXPECT_TRUE(Contains(config_error(with(base, "/V_a/5", -3)), "'V_a[5]' = -3 must be greater than 'v_min' = -3"));
}

TEST(ConfigParse, RejectsBadTruth) {
  const json base = valid_document();
  EXPECT_TRUE(Contains(config_error(with(base, "/truth", json::array())), "'truth' must be a JSON object, got array"));
  EXPECT_TRUE(
      Contains(config_error(with(base, "/truth", {{"a", {1, 2, 3}}})), "'truth.a' must have n = 2 entries, got 3"));
  EXPECT_TRUE(Contains(config_error(with(base, "/truth", {{"b", {1, "2"}}})), "'truth.b[1]' must be a number"));
  EXPECT_TRUE(Contains(config_error(with(base, "/truth", {{"F_a", {1}}})), "'truth.F_a' must have m = 6 entries"));
  EXPECT_TRUE(Contains(config_error(with(without(base, "V_d"), "/truth", {{"F_d", {1, 2, 3, 4, 5, 6}}})),
                       "'truth.F_d' is given but 'V_d' is absent"));
  EXPECT_TRUE(Contains(config_error(with(base, "/truth", {{"ybar0_d", "x"}})), "'truth.ybar0_d' must be a number"));
}

TEST(ConfigIo, ReadRejectsMissingFile) {
  // A name no run creates: this test's own folder, which does not exist.
  const fs::path missing =
      fs::temp_directory_path() / ("lashid_no_such_dir_" + std::to_string(::getpid())) / "config.json";
  EXPECT_EQ(error_of([&] { read_config_json(missing); }), missing.string() + ": file not found");
}

class ConfigFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device entropy;
    dir_ = fs::temp_directory_path() / fmt::format("lashid_config_io_{:08x}{:08x}", entropy(), entropy());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(ConfigFiles, WriteThenReadRoundTripsExactly) {
  // n = 3, m = 2: T = 3 (2 + 3) = 15, so 30 is the shortest pulse experiment; L = 4 = n + 1 the shortest step.
  ExperimentConfig config{3, 2, -0.1, 1.0 / 3.0, {-0.1, 0.2}, {1.0 / 3.0, 0.0}, OperatorKind::kSwitch, Truth{},
                          /*step_length=*/4, /*pulse_length_d=*/30, /*pulse_length_a=*/31, /*val_length=*/0,
                          /*val_seed=*/4294967295U, /*sensor_range=*/std::array<double, 2>{-1e30, 0.1}};
  config.truth->a = {0.1, -2.0 / 7.0, 1e-17};
  config.truth->F_d = {std::nextafter(1.0, 2.0), -5e-324};
  config.truth->ybar0_d = 26.37;
  const fs::path path = dir_ / "config.json";
  write_json_file(path, to_json(config));
  EXPECT_EQ(read_config_json(path), config);

  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  EXPECT_TRUE(text.str().starts_with("{\n  \""));
  EXPECT_TRUE(text.str().ends_with("}\n"));
  EXPECT_FALSE(Contains(text.str(), "\"b\""));  // absent truth fields are not written
}

TEST_F(ConfigFiles, WriteIntoMissingDirectoryCreatesNothing) {
  const fs::path path = dir_ / "missing" / "config.json";
  EXPECT_TRUE(Contains(error_of([&] { write_json_file(path, json::object()); }), "missing' does not exist"));
  EXPECT_FALSE(fs::exists(dir_ / "missing"));
}

// A recording that follows the paper's experiments for the documented example (n = 2, m = 6).
Recording paper_like_recording(const ExperimentConfig& config, std::size_t pulse_length) {
  Recording recording;
  recording.append(Phase::kStepD, config.v_min, 0.0);  // (3.4): v_m at t = 0, then v_M
  for (int t = 1; t <= config.n; ++t) recording.append(Phase::kStepD, config.v_max, 1.0);
  for (std::size_t t = 0; t < pulse_length; ++t) {
    const double v = t % 3 == 1 ? config.V_d[t % config.V_d.size()] : config.v_max;
    recording.append(Phase::kDis, v, 2.0);
  }
  recording.append(Phase::kStepA, config.v_max, 0.0);  // (4.1): v_M at t = 0, then v_m
  for (int t = 1; t <= config.n; ++t) recording.append(Phase::kStepA, config.v_min, 1.0);
  for (std::size_t t = 0; t < pulse_length; ++t) {
    const double v = t % 3 == 1 ? config.V_a[t % config.V_a.size()] : config.v_min;
    recording.append(Phase::kAis, v, 2.0);
  }
  recording.append(Phase::kVal, 100.0, 3.0);  // validation input is unconstrained
  return recording;
}

constexpr std::size_t kExamplePulseMinimum = 2 * 2 * (6 + 3);

TEST(ConfigRecordingMatch, AcceptsPaperLikeRecording) {
  const ExperimentConfig config = parse_config_json(valid_document().dump(), kSource);
  EXPECT_NO_THROW(check_recording_matches(config, paper_like_recording(config, kExamplePulseMinimum), "rec.csv"));
}

TEST(ConfigRecordingMatch, RejectsSchemeMissingFromConfig) {
  const ExperimentConfig full = parse_config_json(valid_document().dump(), kSource);
  const Recording recording = paper_like_recording(full, kExamplePulseMinimum);
  const ExperimentConfig no_dis = parse_config_json(without(valid_document(), "V_d").dump(), kSource);
  EXPECT_EQ(error_of([&] { check_recording_matches(no_dis, recording, "rec.csv"); }),
            "rec.csv: phase 'dis' is recorded but the config has no 'V_d' (the DIS needs its pulse levels)");
  const ExperimentConfig no_ais = parse_config_json(without(valid_document(), "V_a").dump(), kSource);
  EXPECT_TRUE(Contains(error_of([&] { check_recording_matches(no_ais, recording, "rec.csv"); }),
                       "rec.csv: phase 'ais' is recorded but the config has no 'V_a'"));
}

TEST(ConfigRecordingMatch, RejectsInputsOutsideRangeOrOffDesign) {
  const ExperimentConfig config = parse_config_json(valid_document().dump(), kSource);
  Recording out_of_range;
  for (std::size_t t = 0; t < kExamplePulseMinimum; ++t) out_of_range.append(Phase::kDis, t == 5 ? 4.5 : 4.0, 0.0);
  EXPECT_EQ(error_of([&] { check_recording_matches(config, out_of_range, "rec.csv"); }),
            "rec.csv: phase 'dis' t = 5: v = 4.5 is outside [v_min, v_max] = [-3, 4]");

  Recording off_design;
  for (std::size_t t = 0; t < kExamplePulseMinimum; ++t) off_design.append(Phase::kAis, t == 7 ? 0.5 : -3.0, 0.0);
  EXPECT_TRUE(Contains(error_of([&] { check_recording_matches(config, off_design, "rec.csv"); }),
                       "rec.csv: phase 'ais' t = 7: v = 0.5 is not one of the configured levels [4, 3, 2, 1, 0, -1, "
                       "-3]"));

  // A level that went through a lossy text conversion still matches, like in the estimator.
  Recording nearly_on_design;
  for (std::size_t t = 0; t < kExamplePulseMinimum; ++t) {
    nearly_on_design.append(Phase::kDis, std::nextafter(4.0, 5.0), 0.0);
  }
  EXPECT_NO_THROW(check_recording_matches(config, nearly_on_design, "rec.csv"));
}

// On an interval far from 0 the tolerance follows the interval's width and a float32 rounding of the level, not
// |v|: on [1e6, 1e6 + 1] 64 eps32 |v| is 7.6, wider than the interval, and every off-design v matched some level
// (a new-user tryout, session 18). A float32 device's level (float(1e6 + 0.3) = 1000000.3125) still matches.
TEST(ConfigRecordingMatch, FarFromZeroAnOffDesignLevelIsStillRefused) {
  json document = valid_document();
  document["v_min"] = 1e6;
  document["v_max"] = 1e6 + 1;
  document["V_d"] = {1e6, 1e6 + 0.3, 1e6 + 0.5, 1e6 + 0.6, 1e6 + 0.7, 1e6 + 0.8};
  document["V_a"] = {1e6 + 1, 1e6 + 0.8, 1e6 + 0.7, 1e6 + 0.6, 1e6 + 0.5, 1e6 + 0.3};
  const ExperimentConfig config = parse_config_json(document.dump(), kSource);
  const auto dis_with = [](double v) {
    Recording r;
    for (std::size_t t = 0; t < kExamplePulseMinimum; ++t) r.append(Phase::kDis, t == 3 ? v : 1e6 + 1, 0.0);
    return r;
  };
  EXPECT_NO_THROW(check_recording_matches(config, dis_with(static_cast<double>(static_cast<float>(1e6 + 0.3))),
                                          "rec.csv"));
  EXPECT_TRUE(Contains(error_of([&] { check_recording_matches(config, dis_with(1e6 + 0.1), "rec.csv"); }),
                       "rec.csv: phase 'dis' t = 3: v = 1000000.1 is not one of the configured levels"));
}

TEST(ConfigRecordingMatch, RejectsTooShortPhases) {
  const ExperimentConfig config = parse_config_json(valid_document().dump(), kSource);
  Recording short_step;
  short_step.append(Phase::kStepA, 4.0, 0.0);
  short_step.append(Phase::kStepA, -3.0, 0.0);
  EXPECT_TRUE(Contains(error_of([&] { check_recording_matches(config, short_step, "rec.csv"); }),
                       "rec.csv: phase 'step_a' has 2 samples; at least n + 1 = 3 are needed"));

  const Recording short_pulse = paper_like_recording(config, kExamplePulseMinimum - 1);
  EXPECT_TRUE(Contains(error_of([&] { check_recording_matches(config, short_pulse, "rec.csv"); }),
                       "rec.csv: phase 'dis' has 35 samples; at least 2*max(n,2)*(m+3) = 36 are needed (two periods"));
}

TEST(ConfigParse, DeepNestingIsRefusedWhileParsing) {
  // Found by hand (issue 14): 100,000 nested arrays crashed the reader, 50,000 nested objects took 2.5 GB.
  const std::string arrays = "{\"n\": " + std::string(100000, '[') + std::string(100000, ']') + "}";
  EXPECT_EQ(error_of([&] { parse_config_json(arrays, kSource); }),
            "cfg.json: JSON nested deeper than 64 levels of objects and arrays; the project's files need a few");
  std::string objects = "{\"truth\": ";
  for (int i = 0; i < 50000; ++i) objects += "{\"a\": ";
  objects += "1" + std::string(50001, '}');
  EXPECT_TRUE(Contains(error_of([&] { parse_config_json(objects, kSource); }), "nested deeper than 64 levels"));
}

TEST(ConfigParse, AnEchoedValueIsCut) {
  json document = parse_json(R"({"m": 6, "v_min": -3, "v_max": 4, "operator": "switch"})");
  document["n"] = json::array();
  for (int i = 0; i < 100000; ++i) document["n"].push_back(i);
  const std::string message = config_error(document);
  EXPECT_TRUE(Contains(message, "'n' must be an integer, got [0,1,2,3"));
  EXPECT_TRUE(Contains(message, "..."));
  EXPECT_LT(message.size(), 150u);
}

}  // namespace config_io_test
}  // namespace lashid::sim

namespace {

// A float32 device commands float(V_j): for V_j = 1/3 that is 0.3333333432674408, 1.0e-8 away, far beyond the double
// estimator's own matching (64 double eps ~ 2.8e-14 here) and well within half a float32 ulp (3.0e-8).
TEST(RecordingLevels, AFloat32DevicesRecordingMatchesAndIsSnappedToTheConfiguredLevels) {
  const lashid::sim::ExperimentConfig c = lashid::sim::parse_config_json(
      R"({"n": 1, "m": 3, "v_min": -1, "v_max": 1, "operator": "switch",
          "V_d": [-1, -0.3333333333333333, 0.3333333333333333]})",
      "third.json");
  const double third = 1.0 / 3.0;
  const double device_third = static_cast<double>(static_cast<float>(third));
  EXPECT_NEAR(device_third - third, 9.9e-9, 1e-10);  // float(1/3) = 11184811 / 2^25
  // 64 float eps of max(v_max - v_min, |v_min|, |v_max|) = 64 * 2^-23 * 2.
  EXPECT_DOUBLE_EQ(lashid::sim::level_tolerance(c), 64.0 * 2.0 / 8388608.0);
  lashid::sim::Recording rec;
  rec.append(lashid::sim::Phase::kStepD, -1.0, 0.0);
  for (int t = 1; t <= 3; ++t) rec.append(lashid::sim::Phase::kStepD, 1.0, 0.5);
  // Two pulse periods of n = 1, m = 3: T = 2 (3 + 3) = 12, tau = 4, 8, 10.
  for (int t = 0; t < 24; ++t) {
    const int phase = t % 12;
    const double v = phase == 4 ? -1.0 : phase == 8 ? -third : phase == 10 ? device_third : 1.0;
    rec.append(lashid::sim::Phase::kDis, v, 0.1 * t);
  }
  rec.append(lashid::sim::Phase::kVal, device_third, 0.0);
  EXPECT_NO_THROW(lashid::sim::check_recording_matches(c, rec, "rec.csv"));
  const lashid::sim::Recording snapped = lashid::sim::snap_to_configured_levels(c, rec);
  EXPECT_EQ(snapped.phase(lashid::sim::Phase::kDis)[10].v, third);          // the configured level itself
  EXPECT_EQ(snapped.phase(lashid::sim::Phase::kDis)[8].v, -third);          // already exact: unchanged
  EXPECT_EQ(snapped.phase(lashid::sim::Phase::kDis)[11].v, 1.0);
  EXPECT_EQ(snapped.phase(lashid::sim::Phase::kDis)[10].y, 1.0);            // outputs untouched
  EXPECT_EQ(snapped.phase(lashid::sim::Phase::kVal)[0].v, device_third);    // validation inputs untouched
  // An input a thousandth off is no level: refused, naming phase and t.
  lashid::sim::Recording off;
  for (const lashid::sim::Phase p : rec.order()) {
    for (std::size_t t = 0; t < rec.phase(p).size(); ++t) {
      const auto& x = rec.phase(p)[t];
      off.append(p, p == lashid::sim::Phase::kDis && t == 10 ? third + 1e-3 : x.v, x.y);
    }
  }
  EXPECT_TRUE(lashid::test::Contains(lashid::test::error_of([&] { lashid::sim::check_recording_matches(c, off, "rec.csv"); }),
                       "phase 'dis' t = 10: v = "))
      << lashid::test::error_of([&] { lashid::sim::check_recording_matches(c, off, "rec.csv"); });
}

}  // namespace
