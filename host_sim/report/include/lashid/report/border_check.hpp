// Whether an estimate's border is identified at all: the estimator's status says the least squares had a solution
// (a numerical fact), not that the pulse experiment moved the output. A plant whose border is flat (F(V_j) equal to
// the output at the held level for every j: the pulses change nothing) gets status "ok" with b and F made of noise.
#pragma once

#include <string>
#include <vector>

#include "lashid/identify/identify.hpp"
#include "lashid/io/config.hpp"

namespace lashid::report {

/// Level of the test: a flat border is said to be flat with probability at least 1 - kFlatBorderAlpha.
inline constexpr double kFlatBorderAlpha = 0.01;

/// Theta (3.19) holds, for the pulse at level V_l seen at lag i (group k), mu_k with mu_k W_l = b_i (F(V_l) - u_held)
/// + c before the scaling (3.11c): the pulse's effect on the output, plus an offset c common to every group (the step
/// mean ybar0 carries the step phase's start-up transient, and the regression has no intercept: the groups absorb
/// it). A border constant over the levels (the pulses excite nothing) leaves x_k = mu_k W_l equal to c in every
/// group, and the scaling then turns noise into b and F. The test, on the n m values x_k with se_k = se(mu_k) |W_l|:
/// z_k = |x_k - x_w| / se_k, x_w their inverse-variance weighted mean, the largest against the Bonferroni bound
/// z* = Phi^-1(1 - alpha / (2 n m)). Under a flat border each z_k is at most |N(0, 1)| in law (asymptotically), so
/// P(max z_k > z*) <= alpha whatever their correlation. A largest z_k at or below z* means no pulse moved the
/// output distinguishably from the others and from the common offset: the border values are not distinguishable
/// from flat. With n = 1 a border constant over the levels but not at the held level looks the same (each pulse
/// moves y by one amount, confounded with c): also "not distinguishable from flat". Needs n m >= 2.
struct BorderCheck {
  bool applicable = false;  ///< the scheme has a solution and standard errors, and n m >= 2
  double max_z = 0;         ///< largest |x_k - x_w| / se_k
  double threshold = 0;     ///< z*
  bool flat = false;        ///< max_z <= threshold: not distinguishable from a flat border
};

/// The test above on one scheme's result, `levels` its V_d (DIS) or V_a (AIS) and `held` v_max (DIS) or v_min
/// (AIS). A standard error of 0 (a noise-free fit) counts any difference as distinguishable.
BorderCheck check_border(const sim::SchemeResult& result, const std::vector<double>& levels, double held);
/// The same, with the levels and held level of `config` for the result's scheme.
BorderCheck check_border(const sim::ExperimentConfig& config, const sim::SchemeResult& result);

/// One line for the report, empty when the border is identified: what the test found and what it means.
std::string border_warning(const BorderCheck& check);

}  // namespace lashid::report
