// Pieces shared by the fit (joint_model.cpp) and the simulation (joint_model_simulation.cpp) of a JointModel.
#pragma once

#include <cstddef>
#include <memory>

#include "lashid/analysis/joint_model.hpp"
#include "lashid/plant/operators.hpp"

namespace lashid::sim::detail {

/// The model's operator (switch or backlash with its table borders), reset to (w0, C_d(w0)).
std::unique_ptr<HysteresisOperator> make_model_operator(const JointModel& model, double w0);

/// Normalised time t / (samples - 1) in [0, 1]: the regressor of the drift term kappa1.
double tau(std::size_t t, std::size_t samples);

}  // namespace lashid::sim::detail
