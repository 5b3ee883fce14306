#include "sweep_oracle.hpp"

#include <limits>

namespace lashid::app {

using namespace lashid::sim;

std::optional<OracleCheck> oracle_check(const HiddenEffectCase& c, const FlatRecording& data,
                                        const ModelStructure& structure, const JointModel& fit) {
  if (!fit.ok || !c.effect.borders || structure.drift || structure.instrumental || !(c.noise_variance > 0)) {
    return std::nullopt;
  }
  const double unit = static_cast<double>(fit.rows) * c.noise_variance;
  const JointModel truth = with_true_plant(fit, c.model.a, c.model.b, c.effect.borders->first,
                                           c.effect.borders->second);
  // The same structure fitted from the true plant's regimes (its only start).
  const JointModel from_truth = fit_joint_model(c.config, data, structure, &truth, true);
  ModelStructure held = structure;
  held.regime_consistency = true;
  const JointModel consistent = fit_joint_model(c.config, data, held, &truth, true);
  ModelStructure search = structure;
  search.regime_search = true;
  const JointModel searched = fit_joint_model(c.config, data, search);
  const std::size_t val_begin = data.size() - c.recording.phase(Phase::kVal).size();
  const auto val_fit = [&](const JointModel& m) { return simulation_fit(m, data, val_begin, data.size()); };
  OracleCheck check;
  check.truth = self_consistent_rss(truth, data) / unit;
  check.fit_rss = fit.rss / unit;
  check.fit_consistent = self_consistent_rss(fit, data) / unit;
  check.from_true_regimes_rss = from_truth.ok ? from_truth.rss / unit : std::numeric_limits<double>::infinity();
  check.from_true_regimes = from_truth.ok ? self_consistent_rss(from_truth, data) / unit
                                          : std::numeric_limits<double>::infinity();
  check.from_true_regimes_consistent = consistent.ok ? self_consistent_rss(consistent, data) / unit
                                                     : std::numeric_limits<double>::infinity();
  check.regime_search = searched.ok ? self_consistent_rss(searched, data) / unit
                                    : std::numeric_limits<double>::infinity();
  check.val_regime_search = searched.ok ? val_fit(searched) : -std::numeric_limits<double>::infinity();
  check.val_truth = val_fit(truth);
  check.val_fit = val_fit(fit);
  check.val_from_true_regimes = from_truth.ok ? val_fit(from_truth) : -std::numeric_limits<double>::infinity();
  check.val_from_true_regimes_consistent = consistent.ok ? val_fit(consistent)
                                                         : -std::numeric_limits<double>::infinity();
  return check;
}

nlohmann::json to_json(const std::optional<OracleCheck>& check) {
  if (!check) return nullptr;
  return {{"truth", check->truth},
          {"fit_rss", check->fit_rss},
          {"fit_consistent", check->fit_consistent},
          {"from_true_regimes_rss", check->from_true_regimes_rss},
          {"from_true_regimes", check->from_true_regimes},
          {"val_truth", check->val_truth},
          {"val_fit", check->val_fit},
          {"val_from_true_regimes", check->val_from_true_regimes},
          {"from_true_regimes_consistent", check->from_true_regimes_consistent},
          {"val_from_true_regimes_consistent", check->val_from_true_regimes_consistent},
          {"regime_search", check->regime_search},
          {"val_regime_search", check->val_regime_search}};
}

}  // namespace lashid::app
