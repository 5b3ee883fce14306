// The test side of `lashid operator-fit` (cmd_operator_fit.cpp): the band tension of every file, and the fitted
// models simulated, scored, analysed and plotted on every test file.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "lashid/operator_fit/band_tension.hpp"
#include "lashid/operator_fit/operator_fit.hpp"
#include "lashid/operator_fit/output_dynamics.hpp"
#include "lashid/report/plot.hpp"

namespace lashid::app {

// The band tension of every file, and the operator per tension when the training files span two tensions or more.
struct Tensions {
  std::vector<double> train;  // lb, one per training file (empty when the tension model is off)
  std::vector<double> test;   // lb, one per test file (same)
  std::optional<sim::TensionFrictionFit> fit;
  std::string off_reason;     // why the tension model is off
};

// The tension of every file from --tension FILE=LB or the file name (tension_from_file_name). Off when no training
// file has one or all have the same; then test files need none. On: every file needs one, or a clear error
// (std::invalid_argument).
Tensions resolve_tensions(const OperatorFitArgs& args, const std::vector<sim::DamperRecord>& train,
                          const std::vector<sim::DamperRecord>& test);

// What the models do on the test files, one entry per file in the order of the files.
struct TestResults {
  nlohmann::json fit_nominal = nlohmann::json::object();   // file -> fit (%)
  nlohmann::json fit_extended = nlohmann::json::object();  // file -> fit (%)
  nlohmann::json fit_tension = nlohmann::json::object();   // file -> fit (%) of the operator per band tension (when on)
  nlohmann::json fit_dynamics = nlohmann::json::object();  // file -> fit (%) of the final operator followed by B/A
  nlohmann::json loops = nlohmann::json::object();         // file -> the loop analyses
  nlohmann::json profiles = nlohmann::json::object();      // file -> the final model's fit profiles over the record's unknowns
  std::vector<sim::LoopAnalysis> nominal;
  std::vector<sim::LoopAnalysis> final_operator;  // the tension model when on, else the tension-blind extended one
  sim::TestErrors dynamics_gain;  // squared errors of the final operator without and with the dynamics
  sim::TestErrors tension_gain;   // squared errors of the tension-blind and the tension model
  nlohmann::json oscillation_words = nullptr;  // the file whose final-model error is most fast oscillation, in words
};

// Simulates the models on every test file, prints their fits and loop analyses, and adds one panel per file.
TestResults evaluate_test_files(const std::vector<sim::DamperRecord>& test, const sim::NominalFit& nominal,
                                const sim::HysteresisOperator& nominal_op, const sim::FrictionGapOperator& extended_op,
                                const Tensions& tensions, const sim::OutputFilter& dynamics, double rate,
                                const sim::LoopPhaseOptions& phase_options, report::plot::Figure& figure);

// file -> the fit of every model on it.
nlohmann::json summary_json(const TestResults& r);

}  // namespace lashid::app
