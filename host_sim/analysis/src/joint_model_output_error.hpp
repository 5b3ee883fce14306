// The joint model refitted by output error (joint_model_output_error.cpp).
#pragma once

#include <optional>

#include "joint_model_layout.hpp"
#include "lashid/analysis/joint_model.hpp"

namespace lashid::sim::detail {

/// Refits a_i, b_i, the border values (all but the references C_d(v_min) = -1 and u~(v_max) = 0), kappa0 and
/// kappa1 of `model` (whose borders are on `layout`'s abscissas) by minimising the simulation error on the
/// identification phases, each phase simulated from its measured start: Levenberg-Marquardt with the simulated
/// output's sensitivities, the operator's regimes those of the current borders at each step. Steps whose
/// simulation is not finite are refused. Returns whether the simulation error went down; `model` is unchanged
/// otherwise (its residuals are those of the regression it came from: the caller recomputes them). `reached`,
/// when given, receives the simulation error energy reached (the criterion minimised, to compare starts).
bool refine_output_error(JointModel& model, const Layout& layout, const FlatRecording& data,
                         double* reached = nullptr);

/// The output-error fit of the IV model `iv` (refine_output_error) and, with iv.structure.output_error_restarts, of
/// two more starts: the least-squares model `least_squares` and, where iv's A is unstable, iv with A's unstable
/// roots reflected into the unit circle (B scaled to keep the static gain). The refined start with the lowest
/// simulation error on the identification phases is returned, marked output_error, with its one-step residuals
/// and simulation_sse; nullopt when no start could be refined.
std::optional<JointModel> output_error_fit(const JointModel& iv, const JointModel& least_squares,
                                           const Layout& layout, const FlatRecording& data);

}  // namespace lashid::sim::detail
