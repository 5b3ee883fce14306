// The decision of the diagnosis (diagnosis_selection.cpp), called by diagnose() (diagnosis.cpp).
#pragma once

#include <functional>
#include <vector>

#include "diagnosis_candidates.hpp"

namespace lashid::sim::detail {

/// One candidate per cause, in order, made by `make`; the input lag's on a second thread (its search costs about as
/// much as all the others together). The answers do not depend on it.
std::vector<CandidateCause> candidates_for(const std::vector<Cause>& causes,
                                           const std::function<CandidateCause(Cause)>& make);

/// The forward selection from d.nominal and d.candidates (every cause against the nominal model): fills d.added,
/// d.extended, d.fit_extended and d.val_extended (docs/diagnose.md, "Decision").
void select_causes(Diagnosis& d, const ExperimentConfig& config, const FlatRecording& data,
                   const DiagnosisOptions& options);

}  // namespace lashid::sim::detail
