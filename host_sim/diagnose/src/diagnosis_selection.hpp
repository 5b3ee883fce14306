// The decision of the diagnosis (diagnosis_selection.cpp), called by diagnose() (diagnosis.cpp).
#pragma once

#include <vector>

#include "diagnosis_candidates.hpp"

namespace lashid::sim::detail {

/// The forward selection from d.nominal and d.candidates (every cause against the nominal model): fills d.added,
/// d.extended, d.fit_extended and d.val_extended (docs/diagnose.md, "Decision").
void select_causes(Diagnosis& d, const ExperimentConfig& config, const FlatRecording& data,
                   const DiagnosisOptions& options);

}  // namespace lashid::sim::detail
