// Profiles of the final damper model on one test record over two things a test cannot know from its input
// (docs/friction-damper.md, "What still fails"): where the slider sits when the record starts, and the band
// tension. Each profile refits nothing: it simulates the model (operator, then the filter B/A) once per value and
// reports the fit of each. The best value is chosen on the test record itself, so its fit is a bound on what a
// better guess of that one unknown could give, never a score of the model: if even the best value leaves the fit
// far below the target, that unknown is not the cause of the miss.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "lashid/io/damper_data.hpp"
#include "lashid/operator_fit/band_tension.hpp"
#include "lashid/operator_fit/output_dynamics.hpp"
#include "lashid/plant/friction_gap.hpp"

namespace lashid::sim {

struct FitProfile {
  std::string parameter;                         ///< "initial_offset_in" or "tension_lb"
  std::vector<std::pair<double, double>> points;  ///< (value, fit %) for every value tried, in order
  double best_value = 0;                         ///< the value of the highest fit (the first of equal ones)
  double best_fit = 0;                           ///< that fit (%); -inf when every simulation diverged
};

/// The fit of `op` followed by `dynamics` on `record` with the slider placed at each of `points` equally spaced
/// relative displacements e0 over the play [e_lo, e_hi] (FrictionGapOperator::place(v[0], e0)) instead of
/// reset(v[0], u[0]). The first simulated force is the measured u[0], as in simulate_operator(). Throws
/// std::invalid_argument for points < 2 or a record with fewer than 2 samples or a constant force (naming it).
FitProfile initial_offset_profile(const FrictionGapOperator& op, const OutputFilter& dynamics,
                                  const DamperRecord& record, int points = 41);

/// The fit of the model per band tension at each tension lo, lo + step, ..., up to hi (inclusive within 1e-9;
/// outside the training tensions it is extrapolated, TensionFrictionFit::at), followed by `dynamics`, started by
/// reset(v[0], u[0]). A tension whose interpolated operator is invalid (its play no longer contains 0) is left out.
/// Throws std::invalid_argument unless 0 <= lo <= hi and step > 0 are finite, or for a record as above.
FitProfile tension_profile(const TensionFrictionFit& fit, const OutputFilter& dynamics, const DamperRecord& record,
                           double lo, double hi, double step);

}  // namespace lashid::sim
