#include "lashid/diagnose/diagnosis.hpp"

#include <algorithm>
#include <span>
#include <stdexcept>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "diagnosis_candidates.hpp"
#include "lashid/estimator/status.hpp"
#include "diagnosis_selection.hpp"

namespace lashid::sim {

namespace {

using detail::candidates_for;
using detail::extend_model;
using detail::residuals;
using detail::score_candidate;
using detail::select_causes;

// The recording must hold all five phases, match the config, and give the residual tests enough val samples.
void check_diagnosable(const ExperimentConfig& config, const Recording& recording, std::string_view data_name) {
  for (Phase p : kAllPhases) {
    if (!recording.has(p)) {
      throw DataError(data_name, fmt::format("diagnose needs all five phases; '{}' is missing", to_string(p)));
    }
  }
  check_recording_matches(config, recording, data_name);
  const std::size_t min_val = 10 * static_cast<std::size_t>(kResidualLags);
  const auto val = recording.phase(Phase::kVal);
  if (val.size() < min_val) {
    throw DataError(data_name, fmt::format("phase 'val' has {} samples; the residual tests need at least {}",
                                           val.size(), min_val));
  }
  // The fits on val are relative to its variation: a constant output (a sensor stuck, a plant that never moved)
  // gives nothing to judge a model by.
  if (std::all_of(val.begin(), val.end(), [&](const Sample& s) { return s.y == val.front().y; })) {
    throw DataError(data_name, fmt::format("phase 'val' has the same y ({:g}) in all its {} samples: nothing to "
                                           "judge a model by",
                                           val.front().y, val.size()));
  }
  // The residual tests correlate the errors with the input: an input that never moves gives them nothing.
  if (std::all_of(val.begin(), val.end(), [&](const Sample& s) { return s.v == val.front().v; })) {
    throw DataError(data_name, fmt::format("phase 'val' holds v = {:g} in all its {} samples: the residual tests "
                                           "need an input that moves",
                                           val.front().v, val.size()));
  }
  // The identification phases are checked by the estimator (identify_scheme names the sample); val's y must also
  // fit the sums of squares (est::kMaxSampleMagnitude, as there), or the statistics end in NaN.
  for (std::size_t t = 0; t < val.size(); ++t) {
    if (!est::usable(val[t].y)) {
      throw DataError(data_name, fmt::format("phase val t = {}: y = {:g} is too large for the model's sums (at most "
                                             "{:g} in magnitude)",
                                             t, val[t].y, est::kMaxSampleMagnitude<double>));
    }
  }
}

// Every cause's parameters as `model` has them, found or not.
CauseParameters model_parameters(const JointModel& model) {
  CauseParameters p;
  p.lambda = model.structure.input_lag;
  p.delay = model.structure.delay;
  p.drift_total = model.drift_total();
  p.instrumental_variables = model.structure.instrumental;
  p.output_error = model.structure.instrumental && model.structure.output_error;
  p.op = model.structure.op;
  return p;
}

// `all`'s members of the given causes. The JSON's "parameters" are those of every found cause; each step of
// "gain_per_cause" has its own cause's, also as the final model has them: the selection refits after a step was
// taken (lambda searched again with the causes added after it, a drift refitted beside a lag or a dropped cause,
// colored_noise's estimator chosen last), and the steps decompose the final model's gain (their last fit_after is
// the extended fit), so their parameters must be that model's, not the ones a cause had when added.
CauseParameters parameters_of(const CauseParameters& all, std::span<const Cause> causes) {
  CauseParameters p;
  for (const Cause cause : causes) {
    switch (cause) {
      case Cause::kInputLag:
        p.lambda = all.lambda;
        break;
      case Cause::kDeadTime:
        p.delay = all.delay;
        break;
      case Cause::kSensorDrift:
        p.drift_total = all.drift_total;
        break;
      case Cause::kColoredNoise:
        p.instrumental_variables = all.instrumental_variables;
        p.output_error = all.output_error;
        break;
      case Cause::kOperatorType:
        p.op = all.op;
        break;
      case Cause::kNone:
        break;
    }
  }
  return p;
}

}  // namespace

Diagnosis diagnose(const ExperimentConfig& config, const Recording& recording, std::string_view data_name,
                   const DiagnosisOptions& options) {
  check_diagnosable(config, recording, data_name);
  // A float32 device's recording (lashid hil --record) holds float(V_j): the model is fitted on the levels.
  const FlatRecording data = flatten(snap_to_configured_levels(config, recording));
  Diagnosis d;
  std::tie(d.val_begin, d.val_end) = detail::val_range(data);

  // The paper's estimates per scheme, and their disagreement on A and B (Remark 3b, as the firmware reports it).
  d.dis = identify_scheme(config, recording, est::Scheme::kDescending, {}, data_name);
  d.ais = identify_scheme(config, recording, est::Scheme::kAscending, {}, data_name);
  if (d.dis.status == est::Status::kOk && d.ais.status == est::Status::kOk) {
    d.remark3b_z = cross_check(config, d.dis, d.ais).max_z;
  }

  ModelStructure nominal_structure;
  nominal_structure.op = config.op;
  d.nominal = fit_joint_model(config, data, nominal_structure);
  if (!d.nominal.ok) throw std::runtime_error(fmt::format("{}: the nominal model cannot be fitted: {}", data_name,
                                                          d.nominal.failure));
  d.identification = residuals(d.nominal, data, false);
  d.validation = residuals(d.nominal, data, true);
  d.fit_nominal = simulation_fit(d.nominal, data, d.val_begin, d.val_end, &d.val_nominal);
  const std::span<const double> measured(data.y.data() + d.val_begin, d.val_end - d.val_begin);

  // Every cause against the nominal model (the evidence the report shows), then the forward selection.
  std::vector<Cause> causes;
  for (Cause cause : kAllCauses) {
    if (cause != Cause::kNone) causes.push_back(cause);
  }
  d.candidates = candidates_for(causes, [&](Cause cause) {
    CandidateCause c = extend_model(config, data, d.nominal, cause, options);
    score_candidate(c, d.nominal, d.val_nominal, data, d.val_begin, d.val_end, options);
    return c;
  });
  select_causes(d, config, data, options);
  d.causes.clear();
  for (const AddedCause& a : d.added) d.causes.push_back(a.cause);
  if (d.causes.empty()) d.causes.push_back(Cause::kNone);
  d.cause = d.causes.front();
  const CauseParameters final_model = model_parameters(d.extended);
  d.parameters = parameters_of(final_model, d.causes);
  for (AddedCause& a : d.added) a.parameters = parameters_of(final_model, std::span(&a.cause, 1));
  d.val_v.assign(data.v.begin() + static_cast<std::ptrdiff_t>(d.val_begin),
                 data.v.begin() + static_cast<std::ptrdiff_t>(d.val_end));
  d.val_measured.assign(measured.begin(), measured.end());
  d.findings = describe_findings(d);
  return d;
}

}  // namespace lashid::sim
