// Printing and JSON of `lashid operator-fit`.
#include "operator_fit_report.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace lashid::app {

using namespace lashid::sim;
using nlohmann::json;

json table_json(const std::vector<std::pair<double, double>>& table) {
  json out = json::array();
  for (const auto& [x, y] : table) out.push_back({x, y});
  return out;
}

json border_json(const Border& border, int points) {
  std::vector<std::pair<double, double>> table;
  for (int i = 0; i < points; ++i) {
    const double v = border.lo() + (border.hi() - border.lo()) * i / (points - 1);
    table.emplace_back(v, border(v));
  }
  return table_json(table);
}

json analysis_json(const LoopAnalysis& a) {
  json phases = json::object();
  for (const auto& p : a.phases) {
    phases[p.phase] = {{"samples", p.samples}, {"share_of_squared_error", p.share_of_squared_error}, {"rms", p.rms}};
  }
  return {{"phases", phases},
          {"reversals", a.reversals},
          {"plateau", a.plateau},
          {"measured_reversal_slope", a.measured_reversal_slope},
          {"simulated_reversal_slope", a.simulated_reversal_slope},
          {"measured_gap", a.measured_gap},
          {"simulated_gap", a.simulated_gap},
          {"measured_gap_centre_spread", a.measured_gap_centre_spread},
          {"peak_speed", a.peak_speed}};
}

void print_analysis(const std::string& model, const LoopAnalysis& a, std::size_t n, const LoopPhaseOptions& o) {
  fmt::print("  {} model, error by phase of the loop ({} reversals):\n", model, a.reversals);
  for (const auto& p : a.phases) {
    fmt::print("    {:<11} {:5.1f} % of the samples, {:5.1f} % of the squared error, RMS {:.3f}\n", p.phase,
               100.0 * static_cast<double>(p.samples) / static_cast<double>(n), 100.0 * p.share_of_squared_error,
               p.rms);
  }
  const auto worst = std::max_element(a.phases.begin(), a.phases.end(), [](const auto& x, const auto& y) {
    return x.share_of_squared_error < y.share_of_squared_error;
  });
  fmt::print("    In words: {:.0f} % of the squared error is in the {} phase. Over the first {} of travel after a "
             "reversal the measured force changes at {:.1f} per unit of v, the simulation at {:.1f}; per half-cycle "
             "the measured force stays below 10 % of the friction level ({:.2f}) for {:.3f} of travel, the "
             "simulated one for {:.3f}.\n",
             100.0 * worst->share_of_squared_error, worst->phase, o.reversal_window, a.measured_reversal_slope,
             a.simulated_reversal_slope, a.plateau, a.measured_gap, a.simulated_gap);
}


json causes_json(const std::vector<DamperCause>& causes) {
  json out = json::array();
  for (const auto& c : causes) {
    out.push_back({{"name", c.name}, {"in_extended_model", c.in_extended_model}, {"evidence", c.evidence}});
  }
  return out;
}

void print_causes(const std::vector<DamperCause>& causes) {
  fmt::print("\nCauses supported by the errors on the test files:\n");
  for (const auto& c : causes) {
    fmt::print("  - {} ({}): {}\n", c.name, c.in_extended_model ? "in the extended model" : "not modelled",
               c.evidence);
  }
}


namespace {

json pole_json(const FilterPole& p) {
  return {{"re", p.z.real()},           {"im", p.z.imag()},           {"magnitude", std::abs(p.z)},
          {"natural_hz", p.natural_hz}, {"damped_hz", p.damped_hz}, {"zeta", p.zeta}};
}

}  // namespace

json dynamics_json(const OutputDynamicsFit& fit, const std::vector<FilterPole>& poles, double rate,
                   const std::string& structure, const json& fit_test) {
  json scores = json::array(), pole_list = json::array();
  for (const auto& s : fit.scores) scores.push_back({{"order", s.order}, {"cv_fit", s.cv_fit}});
  for (const auto& p : poles) pole_list.push_back(pole_json(p));
  FilterPole dominant;
  const bool has_dominant = dominant_pole(poles, &dominant);
  return {{"model",
           {{"structure", structure},
            {"order", fit.filter.order()},
            {"a", fit.filter.a},
            {"b", fit.filter.b},
            {"dc_gain", fit.filter.dc_gain()},
            {"sample_rate_hz", rate},
            {"poles", pole_list},
            {"dominant_pole", has_dominant ? pole_json(dominant) : json(nullptr)}}},
          {"order_selection", {{"method", "leave one training file out"}, {"scores", scores}}},
          {"fit_train", fit.fit_train},
          {"fit_test", fit_test}};
}

void print_dynamics(const OutputDynamicsFit& fit, const std::vector<FilterPole>& poles) {
  fmt::print("Dynamics after the extended operator, B(q)/A(q) of order {} (orders by leave-one-training-file-out "
             "fit:",
             fit.filter.order());
  for (const auto& s : fit.scores) fmt::print(" {}: {:.1f} %", s.order, s.cv_fit);
  fmt::print("): static gain {:.3f}, training fit {:.1f} %\n  poles:", fit.filter.dc_gain(), fit.fit_train);
  for (const auto& p : poles) {
    fmt::print(" {:.5f}{:+.5f}i ({:.2f} Hz, zeta {:.3f})", p.z.real(), p.z.imag(), p.natural_hz, p.zeta);
  }
  fmt::print("\n\n");
}


json nominal_json(const NominalFit& nominal, int points, const json& fit_test) {
  return {{"operator", nominal.chosen},
          {"fit_train", {{"switch", nominal.fit_train_switch}, {"backlash", nominal.fit_train_backlash}}},
          {"ascending", border_json(nominal.ascending, points)},
          {"descending", border_json(nominal.descending, points)},
          {"fit_test", fit_test}};
}

json extended_json(const ExtendedFit& extended, const HysteresisOperator& extended_op, const json& fit_test) {
  return {{"model",
           {{"operator", extended_op.name()},
            {"half_width", extended.half_width},
            {"stiffness", extended.stiffness},
            {"curve", table_json(extended.curve)},
            {"train_rms_by_half_width", table_json(extended.train_error_by_width)}}},
          {"fit_train", extended.fit_train},
          {"fit_test", fit_test}};
}


json tension_json(const TensionFrictionFit& fit, const json& fit_test) {
  json per_tension = json::array();
  for (const auto& c : fit.tensions) {
    per_tension.push_back({{"tension_lb", c.tension_lb},
                           {"half_width", c.half_width},
                           {"train_rms_by_half_width", table_json(c.train_error_by_width)},
                           {"training_files", c.files},
                           {"stiffness", c.stiffness},
                           {"plateau_up", c.curve.back().second},
                           {"plateau_down", c.curve.front().second},
                           {"curve", table_json(c.curve)}});
  }
  return {{"model",
           {{"operator", "friction_gap per band tension"},
            {"interpolation", "r, k and the nodes of G linear in the tension between the two nearest training tensions"},
            {"plateau_up_per_lb", fit.plateau_slope(true)},
            {"plateau_down_per_lb", fit.plateau_slope(false)},
            {"tensions", per_tension}}},
          {"fit_train", fit.fit_train},
          {"fit_test", fit_test}};
}

void print_tension(const TensionFrictionFit& fit) {
  fmt::print("Extended operator per band tension: ");
  for (const auto& c : fit.tensions) {
    fmt::print("{:g} lb ({} training files): r = {:.3f}, G(+r) = {:.3f}, G(-r) = {:.3f}, k = {:.4f}; ", c.tension_lb,
               c.files, c.half_width, c.curve.back().second, c.curve.front().second, c.stiffness);
  }
  fmt::print("plateau slopes {:+.4f} (up) and {:+.4f} (down) per lb; training fit {:.1f} % (each file at its own "
             "tension)\n\n",
             fit.plateau_slope(true), fit.plateau_slope(false), fit.fit_train);
}

report::plot::Panel fitted_models_panel(const NominalFit& nominal, const ExtendedFit& extended,
                                        const TensionFrictionFit* tension) {
  const auto series = [](const std::string& name, const std::vector<std::pair<double, double>>& table) {
    report::plot::Series s{name, {}, {}};
    for (const auto& [e, g] : table) {
      s.x.push_back(e);
      s.y.push_back(g);
    }
    return s;
  };
  report::plot::Panel panel{"fitted models", "v (borders) or e = v - z (G)", "force u",
                            {{"nominal C_a", {}, {}}, {"nominal C_d", {}, {}},
                             series("friction_gap G(e), tension-blind", extended.curve)}};
  for (std::size_t k = 0; k < 2; ++k) {
    const Border& b = k == 0 ? nominal.ascending : nominal.descending;
    for (int i = 0; i < 200; ++i) {
      const double v = b.lo() + (b.hi() - b.lo()) * i / 199.0;
      panel.series[k].x.push_back(v);
      panel.series[k].y.push_back(b(v));
    }
  }
  if (tension != nullptr) {
    for (const auto& c : tension->tensions) {
      panel.series.push_back(series(fmt::format("friction_gap G(e) at {:g} lb", c.tension_lb), c.curve));
    }
  }
  return panel;
}

json profile_json(const sim::FitProfile& profile) {
  json points = json::array();
  for (const auto& [value, fit] : profile.points) points.push_back({value, fit});
  return {{"parameter", profile.parameter},
          {"points", points},
          {"best_value", profile.best_value},
          {"best_fit", profile.best_fit}};
}

void print_profile(const sim::FitProfile& profile, const std::string& what, double used_fit) {
  fmt::print("  {}: the final model fits {:.1f} % as run; the best of {} values, {} = {:.3g}, fits {:.1f} % (chosen "
             "on this file: a bound, not a score)\n",
             what, used_fit, profile.points.size(), profile.parameter, profile.best_value, profile.best_fit);
}

json oscillation_json(const std::string& model, const ErrorOscillation& oscillation, double ceiling,
                      const DisplacementEcho& echo, const std::string& echo_words) {
  return {{"model", model},
          {"fast_share", oscillation.fast_share},
          {"peak_hz", oscillation.peak_hz},
          {"peak_amplitude", oscillation.peak_amplitude},
          {"fit_ceiling_without_it", ceiling},
          {"displacement_echo",
           {{"hz", echo.hz}, {"coherence", echo.coherence}, {"gain", echo.gain}, {"phase_deg", echo.phase_deg},
            {"windows", echo.windows}, {"text", echo_words}}}};
}

void print_oscillation_words(const json& words) {
  if (words.is_null()) return;
  fmt::print("  - what the final model misses most: on {}, {:.0f} % of its error changes faster than about 10 Hz, "
             "peaking at {:.0f} Hz (a model that misses it fits at most {:.1f} %); that part is {}\n",
             words["file"].get<std::string>(), 100 * words["fast_share"].get<double>(),
             words["peak_hz"].get<double>(), words["fit_ceiling_without_it"].get<double>(),
             words["text"].get<std::string>());
}

}  // namespace lashid::app
