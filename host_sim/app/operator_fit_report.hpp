// Printing and JSON of `lashid operator-fit` (cmd_operator_fit.cpp): the fitted models, loop analyses, causes.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "lashid/operator_fit/band_tension.hpp"
#include "lashid/operator_fit/damper_causes.hpp"
#include "lashid/operator_fit/displacement_echo.hpp"
#include "lashid/operator_fit/operator_fit.hpp"
#include "lashid/operator_fit/output_dynamics.hpp"
#include "lashid/operator_fit/test_profiles.hpp"
#include "lashid/report/plot.hpp"

namespace lashid::app {

nlohmann::json table_json(const std::vector<std::pair<double, double>>& table);
/// The border on `points` equally spaced abscissas of its domain.
nlohmann::json border_json(const sim::Border& border, int points);
nlohmann::json analysis_json(const sim::LoopAnalysis& a);
/// The analysis of one model on one file (`n` samples) in lines and one sentence.
void print_analysis(const std::string& model, const sim::LoopAnalysis& a, std::size_t n,
                    const sim::LoopPhaseOptions& o);
nlohmann::json causes_json(const std::vector<sim::DamperCause>& causes);
void print_causes(const std::vector<sim::DamperCause>& causes);
/// The filter after the operator (`structure` names the chain), its order selection and its fits.
nlohmann::json dynamics_json(const sim::OutputDynamicsFit& fit, const std::vector<sim::FilterPole>& poles,
                             double rate, const std::string& structure, const nlohmann::json& fit_test);
void print_dynamics(const sim::OutputDynamicsFit& fit, const std::vector<sim::FilterPole>& poles);
nlohmann::json nominal_json(const sim::NominalFit& nominal, int points, const nlohmann::json& fit_test);
nlohmann::json extended_json(const sim::ExtendedFit& extended, const sim::HysteresisOperator& extended_op,
                             const nlohmann::json& fit_test);
/// The operator per band tension: r, G and k per training tension, the plateau slopes, and its test fits.
nlohmann::json tension_json(const sim::TensionFrictionFit& fit, const nlohmann::json& fit_test);
void print_tension(const sim::TensionFrictionFit& fit);
/// A test file's fast error (error_oscillation) and the displacement's echo of it (displacement_echo).
nlohmann::json oscillation_json(const std::string& model, const sim::ErrorOscillation& oscillation, double ceiling,
                                const sim::DisplacementEcho& echo, const std::string& echo_words);
/// The file whose final-model error is most fast oscillation, in words (nothing for null).
void print_oscillation_words(const nlohmann::json& words);
/// A profile over an unknown of a test record (test_profiles.hpp): every (value, fit) and the best.
nlohmann::json profile_json(const sim::FitProfile& profile);
/// One line: the fit at the value used, and the best value and its fit, as a bound and not a score.
void print_profile(const sim::FitProfile& profile, const std::string& what, double used_fit);
/// The figure's last panel: the nominal borders and G of the extended operator (and of each training tension).
report::plot::Panel fitted_models_panel(const sim::NominalFit& nominal, const sim::ExtendedFit& extended,
                                        const sim::TensionFrictionFit* tension);

}  // namespace lashid::app
