// The JSON documents `lashid` writes (docs/data-format.md): one function per result type. The domain layers
// (identify/, diagnose/) know nothing of JSON; this is where their results become documents.
#pragma once

#include <nlohmann/json.hpp>

#include "lashid/analysis/joint_model.hpp"
#include "lashid/diagnose/diagnosis.hpp"
#include "lashid/identify/identify.hpp"
#include "lashid/io/json.hpp"

namespace lashid::sim {

/// {"a":[...],"b":[...],"F":[...],"theta":[...], ...diagnostics} as in docs/data-format.md.
nlohmann::json to_json(const SchemeResult& result);
/// The same with `border_check` and `warnings` (border_check.hpp): what `lashid identify --json` writes.
nlohmann::json to_json(const SchemeResult& result, const ExperimentConfig& config);
/// Only the parameter of the cause, e.g. {"lambda": 0.31}; {} for none.
nlohmann::json to_json(const CauseParameters& parameters);
nlohmann::json to_json(const JointModel& model);
/// The `lashid diagnose --json` document: cause, parameters, fits, findings, evidence, models, paper estimates.
nlohmann::json to_json(const Diagnosis& diagnosis);

}  // namespace lashid::sim
