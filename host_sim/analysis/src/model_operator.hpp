// Pieces shared by the fit (joint_model.cpp) and the simulation (joint_model_simulation.cpp) of a JointModel.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "lashid/analysis/joint_model.hpp"
#include "lashid/plant/border.hpp"
#include "lashid/plant/operators.hpp"

namespace lashid::sim::detail {

/// One of the model's border tables (abscissas x, values u) as a Border: linear between its points, constant
/// beyond its ends.
Border table_border(const std::vector<double>& x, const std::vector<double>& u);

/// The model's operator (switch or backlash with its table borders), reset to (w0, C_d(w0)).
std::unique_ptr<HysteresisOperator> make_model_operator(const JointModel& model, double w0);

/// The model's one-step prediction errors on its residual rows (model.residual_t, in order), its operator run on its
/// own borders: the residuals of the model itself rather than of the regression it came from.
std::vector<double> own_residuals(const JointModel& model, const FlatRecording& data);

/// Normalised time t / (samples - 1) in [0, 1]: the regressor of the drift term kappa1.
double tau(std::size_t t, std::size_t samples);

}  // namespace lashid::sim::detail
