// Plant file JSON (docs/data-format.md, "Plant file"): every error names the file and the key; optional keys take
// their documented defaults; unknown keys are listed, not refused; A must be stable.
#include <unistd.h>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "json_text.hpp"

#include "lashid/io/plant_file.hpp"

#include "data_error_matchers.hpp"

namespace lashid::sim {
namespace plant_file_test {

using nlohmann::json;
using test::Contains;
using test::error_of;

constexpr std::string_view kSource = "plant.json";

json valid_document() {
  return parse_json(R"({"operator": "backlash",
                         "borders": {"v": [-3, 0, 4], "ascending": [-2, -0.5, 1.5], "descending": [-1.5, 0.5, 2]},
                         "a": [-1.2, 0.35], "b": [0.5, 0.25],
                         "equation_noise_std": 0.1})");
}

json with(json document, const std::string& pointer, json value) {
  document[json::json_pointer(pointer)] = std::move(value);
  return document;
}

json without(json document, const std::string& pointer) {
  const json::json_pointer p(pointer);
  document[p.parent_pointer()].erase(p.back());
  return document;
}

std::string plant_error(const json& document) {
  return error_of([&] { parse_plant_json(document.dump(), kSource); });
}

TEST(PlantFile, ReadsAMinimalFileWithTheDocumentedDefaults) {
  const PlantSpec p = parse_plant_json(valid_document().dump(), kSource);
  EXPECT_EQ(p.op, OperatorKind::kBacklash);
  EXPECT_EQ(p.border_v, (std::vector<double>{-3, 0, 4}));
  EXPECT_EQ(p.border_ascending, (std::vector<double>{-2, -0.5, 1.5}));
  EXPECT_EQ(p.border_descending, (std::vector<double>{-1.5, 0.5, 2}));
  EXPECT_EQ(p.a, (std::vector<double>{-1.2, 0.35}));
  EXPECT_EQ(p.b, (std::vector<double>{0.5, 0.25}));
  EXPECT_EQ(p.equation_noise_std, 0.1);
  EXPECT_FALSE(p.sensor_noise);
  EXPECT_EQ(p.input_lag, 0.0);
  EXPECT_EQ(p.dead_time, 0);
  EXPECT_EQ(p.sensor_drift_per_sample, 0.0);
  EXPECT_TRUE(p.ignored_keys.empty());
}

TEST(PlantFile, ReadsEveryOptionalKey) {
  json d = valid_document();
  d["operator"] = "switch";
  d["sensor_noise"] = {{"std", 0.2}, {"pole", -0.5}};
  d["input_lag"] = 0.3;
  d["dead_time"] = 2;
  d["sensor_drift_per_sample"] = -1e-4;
  const PlantSpec p = parse_plant_json(d.dump(), kSource);
  EXPECT_EQ(p.op, OperatorKind::kSwitch);
  ASSERT_TRUE(p.sensor_noise);
  EXPECT_EQ(*p.sensor_noise, (SensorNoiseSpec{0.2, -0.5}));
  EXPECT_EQ(p.input_lag, 0.3);
  EXPECT_EQ(p.dead_time, 2);
  EXPECT_EQ(p.sensor_drift_per_sample, -1e-4);
}

TEST(PlantFile, NullOptionalKeysCountAsAbsent) {
  json d = valid_document();
  d["sensor_noise"] = nullptr;
  d["dead_time"] = nullptr;
  const PlantSpec p = parse_plant_json(d.dump(), kSource);
  EXPECT_FALSE(p.sensor_noise);
  EXPECT_EQ(p.dead_time, 0);
}

TEST(PlantFile, UnknownKeysAreIgnoredAndListedWithTheirPath) {
  json d = valid_document();
  d["name"] = "rig 3";
  d["borders"]["unit"] = "mm";
  d["sensor_noise"] = {{"std", 0.1}, {"pole", 0}, {"source", "datasheet"}};
  const PlantSpec p = parse_plant_json(d.dump(), kSource);
  EXPECT_EQ(p.ignored_keys, (std::vector<std::string>{"name", "borders.unit", "sensor_noise.source"}));
}

TEST(PlantFile, MissingRequiredKeysAreNamed) {
  for (const char* key : {"operator", "borders", "a", "b", "equation_noise_std"}) {
    EXPECT_TRUE(Contains(plant_error(without(valid_document(), std::string("/") + key)),
                         fmt::format("plant.json: missing required key '{}'", key)));
  }
  for (const char* key : {"v", "ascending", "descending"}) {
    EXPECT_TRUE(Contains(plant_error(without(valid_document(), std::string("/borders/") + key)),
                         fmt::format("plant.json: missing required key 'borders.{}'", key)));
  }
  EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/sensor_noise", {{"std", 0.1}})),
                       "missing required key 'sensor_noise.pole'"));
}

TEST(PlantFile, BorderErrorsNameTheKey) {
  EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/borders/ascending", {1, 2, 3, 4})),
                       "plant.json: 'borders.ascending' has 4 points, 'borders.v' has 3"));
  EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/borders/descending", {1, 2})),
                       "'borders.descending' has 2 points, 'borders.v' has 3"));
  EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/borders/v", {-3, 0, 0})),
                       "'borders.v[2]' = 0 must be greater than 'borders.v[1]' = 0 (borders.v is strictly increasing)"));
  EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/borders/v", {1})),
                       "'borders.v' needs at least 2 points, got 1"));
  EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/borders/ascending/1", "x")),
                       "'borders.ascending[1]' must be a number, got \"x\""));
  EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/borders", json::array())),
                       "'borders' must be a JSON object"));
  EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/borders/v", 3)), "'borders.v' must be an array"));
}

TEST(PlantFile, LinearPartErrorsNameTheKey) {
  EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/b", {1.0})),
                       "plant.json: 'a' and 'b' must have the same length n >= 1 (got 2 and 1)"));
  EXPECT_TRUE(Contains(plant_error(with(with(valid_document(), "/a", json::array()), "/b", json::array())),
                       "'a' and 'b' must have the same length n >= 1 (got 0 and 0)"));
  EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/a/0", "1")), "'a[0]' must be a number"));
  EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/equation_noise_std", -1)),
                       "'equation_noise_std' = -1 must not be negative"));
  EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/operator", "Backlash")),
                       "'operator' must be \"switch\" or \"backlash\", got \"Backlash\""));
}

// Stability of A(z^-1) = 1 + a1 z^-1 + ...: poles computed by hand for each case.
TEST(PlantFile, AnUnstableOrMarginalAIsRefusedAndAStableOneRead) {
  const auto unstable = [](std::vector<double> a) {
    const std::vector<double> b(a.size(), 1.0);
    return plant_error(with(with(valid_document(), "/a", a), "/b", b));
  };
  EXPECT_TRUE(Contains(unstable({-1.2}), "plant.json: 'a' = [-1.2]: A(q^-1) has a pole on or outside the unit circle"));
  EXPECT_TRUE(Contains(unstable({-1.0}), "'a' = [-1]"));              // integrator: pole at 1
  EXPECT_TRUE(Contains(unstable({-2.5, 1.0}), "unit circle"));        // poles 2, 0.5
  EXPECT_TRUE(Contains(unstable({0.0, 1.0}), "unit circle"));         // poles +-i, on the circle
  EXPECT_TRUE(Contains(unstable({-0.5, -0.5}), "unit circle"));       // poles 1, -0.5
  EXPECT_TRUE(Contains(unstable({0.0, 0.0, 1.21}), "unit circle"));   // |pole| = 1.21^(1/3) > 1
  // Stable: poles 0.7 and 0.5 (1 - 1.2 z^-1 + 0.35 z^-2), 0.9 +- 0.3i (|p| = 0.95), 0.5^3 at 0.5.
  for (const std::vector<double>& a : {std::vector<double>{-1.2, 0.35}, std::vector<double>{-1.8, 0.9},
                                       std::vector<double>{-1.5, 0.75, -0.125}}) {
    const std::vector<double> b(a.size(), 1.0);
    EXPECT_NO_THROW(parse_plant_json(with(with(valid_document(), "/a", a), "/b", b).dump(), kSource));
  }
}

TEST(PlantFile, OptionalKeyErrorsNameTheKey) {
  EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/sensor_noise", {{"std", 0.1}, {"pole", 1.2}})),
                       "plant.json: 'sensor_noise.pole' = 1.2 must lie in (-1, 1)"));
  EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/sensor_noise", {{"std", -0.1}, {"pole", 0}})),
                       "'sensor_noise.std' = -0.1 must not be negative"));
  EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/sensor_noise", 0.1)),
                       "'sensor_noise' must be a JSON object"));
  for (const json& bad : {json(1.5), json(-1), json(2.0), json("2")}) {
    EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/dead_time", bad)),
                         "plant.json: 'dead_time' must be a non-negative integer"))
        << bad.dump();
  }
  EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/dead_time", kMaxDeadTime + 1)),
                       fmt::format("'dead_time' = {} exceeds the limit of {} samples", kMaxDeadTime + 1,
                                   kMaxDeadTime)));
  EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/input_lag", 1.0)), "'input_lag' = 1 must lie in [0, 1)"));
  EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/input_lag", -0.1)), "'input_lag' = -0.1 must lie in"));
  EXPECT_TRUE(Contains(plant_error(with(valid_document(), "/sensor_drift_per_sample", "fast")),
                       "'sensor_drift_per_sample' must be a number"));
}

TEST(PlantFile, SyntaxErrorsDuplicatesAndHugeNumbersAreDataErrors) {
  EXPECT_TRUE(Contains(error_of([] { parse_plant_json("{\n\"a\": [1,,]}", kSource); }), "plant.json:2: invalid JSON"));
  EXPECT_TRUE(Contains(error_of([] { parse_plant_json(R"({"a": [0.5], "a": [0.5]})", kSource); }),
                       "plant.json: duplicate key 'a'"));
  EXPECT_TRUE(Contains(error_of([] { parse_plant_json(R"({"equation_noise_std": 1e999})", kSource); }),
                       "(at key 'equation_noise_std')"));
  EXPECT_TRUE(Contains(error_of([] { parse_plant_json("[1, 2]", kSource); }),
                       "the top level must be a JSON object, got array"));
}

TEST(PlantFile, ReadingAFileNamesIt) {
  // The pid in the name: another build tree may run this test at the same time.
  const auto path = std::filesystem::temp_directory_path() /
                    ("lashid_test_plant_file_" + std::to_string(::getpid()) + ".json");
  std::ofstream(path) << with(valid_document(), "/b", {1.0}).dump();
  EXPECT_TRUE(Contains(error_of([&] { read_plant_json(path); }), path.string() + ": 'a' and 'b'"));
  std::filesystem::remove(path);
  EXPECT_TRUE(Contains(error_of([&] { read_plant_json(path); }), path.string() + ": file not found"));
}

TEST(PlantFile, BordersMustCoverTheDesignInterval) {
  const PlantSpec p = parse_plant_json(valid_document().dump(), kSource);
  EXPECT_NO_THROW(check_plant_covers(p, -3, 4, kSource));
  EXPECT_NO_THROW(check_plant_covers(p, -1, 2, kSource));
  EXPECT_TRUE(Contains(error_of([&] { check_plant_covers(p, -3.5, 4, kSource); }),
                       "plant.json: 'borders.v' covers [-3, 4], which does not contain the design's working interval "
                       "[v_min, v_max] = [-3.5, 4]"));
  EXPECT_TRUE(Contains(error_of([&] { check_plant_covers(p, -3, 4.5, kSource); }), "'borders.v' covers"));
}

}  // namespace plant_file_test
}  // namespace lashid::sim
