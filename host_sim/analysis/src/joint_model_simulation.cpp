// Simulation and one-step prediction of a JointModel, and the flat view of a recording it works on.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "lashid/analysis/joint_model.hpp"
#include "lashid/plant/border.hpp"
#include "lashid/plant/operators.hpp"
#include "lashid/stats/metrics.hpp"
#include "joint_model_layout.hpp"
#include "model_operator.hpp"

namespace lashid::sim {

namespace detail {

Border table_border(const std::vector<double>& x, const std::vector<double>& u) {
  std::vector<std::pair<double, double>> points;
  for (std::size_t i = 0; i < x.size(); ++i) points.emplace_back(x[i], u[i]);
  return Border::from_table(std::move(points));
}

std::unique_ptr<HysteresisOperator> make_model_operator(const JointModel& model, double w0) {
  Border asc = table_border(model.ascending_v, model.ascending_u);
  Border desc = table_border(model.descending_v, model.descending_u);
  const double u0 = desc(w0);
  std::unique_ptr<HysteresisOperator> op;
  if (model.structure.op == OperatorKind::kSwitch) {
    op = std::make_unique<SwitchOperator>(std::move(asc), std::move(desc));
  } else {
    op = std::make_unique<BacklashOperator>(std::move(asc), std::move(desc));
  }
  op->reset(w0, u0);
  return op;
}

double tau(std::size_t t, std::size_t samples) {
  return samples > 1 ? static_cast<double>(t) / static_cast<double>(samples - 1) : 0.0;
}

}  // namespace detail

using detail::make_model_operator;
using detail::tau;

std::vector<double> operator_output(const JointModel& model, const FlatRecording& data) {
  const std::vector<double> w = effective_input(data.v, model.structure);
  std::vector<double> u(w.size());
  if (w.empty()) return u;
  auto op = make_model_operator(model, w[0]);
  for (std::size_t t = 0; t < w.size(); ++t) u[t] = op->step(w[t]);
  return u;
}

namespace {

// y(t) of the model's equation given the past outputs `past(t - i)` and the operator outputs u.
template <class Past>
double model_equation(const JointModel& model, const FlatRecording& data, const std::vector<double>& u, std::size_t t,
                      Past past) {
  double y = model.kappa0 + model.kappa1 * tau(t, data.size());
  for (int i = 1; i <= model.n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double u_lag = t >= k ? u[t - k] : u[0];
    y += -model.a[k - 1] * past(t, k) + model.b[k - 1] * u_lag;
  }
  return y;
}

}  // namespace

std::vector<double> simulate_segment(const JointModel& model, const FlatRecording& data, std::size_t begin,
                                     std::size_t end) {
  if (begin > end || end > data.size()) throw std::out_of_range("simulate_segment: bad sample range");
  const std::vector<double> u = operator_output(model, data);
  std::vector<double> ys(end - begin);
  const auto past = [&](std::size_t t, std::size_t k) {
    if (t >= k && t - k >= begin) return ys[t - k - begin];
    return t >= k ? data.y[t - k] : data.y[0];
  };
  for (std::size_t t = begin; t < end; ++t) ys[t - begin] = model_equation(model, data, u, t, past);
  return ys;
}

std::vector<double> prediction_errors(const JointModel& model, const FlatRecording& data, std::size_t begin,
                                      std::size_t end) {
  if (begin > end || end > data.size()) throw std::out_of_range("prediction_errors: bad sample range");
  const std::vector<double> u = operator_output(model, data);
  std::vector<double> e;
  const auto past = [&](std::size_t t, std::size_t k) { return t >= k ? data.y[t - k] : data.y[0]; };
  for (std::size_t t = std::max(begin, static_cast<std::size_t>(model.n)); t < end; ++t) {
    e.push_back(data.y[t] - model_equation(model, data, u, t, past));
  }
  return e;
}

double simulation_fit(const JointModel& model, const FlatRecording& data, std::size_t begin, std::size_t end,
                      std::vector<double>* simulated) {
  std::vector<double> sim = simulate_segment(model, data, begin, end);
  const std::span<const double> measured(data.y.data() + begin, end - begin);
  const bool finite = std::all_of(sim.begin(), sim.end(), [](double x) { return std::isfinite(x); });
  const double fit = finite ? stats::fit_percent(measured, sim) : -std::numeric_limits<double>::infinity();
  if (simulated != nullptr) *simulated = std::move(sim);
  return fit;
}

std::vector<double> detail::own_residuals(const JointModel& model, const FlatRecording& data) {
  const std::vector<double> e = prediction_errors(model, data, 0, data.size());
  std::vector<double> out;
  out.reserve(model.residual_t.size());
  for (std::size_t t : model.residual_t) out.push_back(e.at(t - static_cast<std::size_t>(model.n)));
  return out;
}

double self_consistent_rss(const JointModel& model, const FlatRecording& data) {
  if (!model.ok) throw std::invalid_argument("self_consistent_rss: the model is not fitted");
  double sum = 0;
  for (double e : detail::own_residuals(model, data)) sum += e * e;
  return sum;
}

JointModel with_true_plant(const JointModel& model, const std::vector<double>& a, const std::vector<double>& b,
                           const Border& ascending, const Border& descending) {
  const auto n = static_cast<std::size_t>(model.n);
  if (a.size() != n || b.size() != n) {
    throw std::invalid_argument("with_true_plant: a and b need " + std::to_string(n) + " coefficients each");
  }
  const double u_max = descending(model.v_max);
  const double rise = u_max - descending(model.v_min);
  if (!(rise != 0.0) || !std::isfinite(rise)) throw std::invalid_argument("with_true_plant: C_d(v_max) = C_d(v_min)");
  JointModel truth = model;
  truth.a = a;
  truth.b = b;
  double b_sum = 0;
  for (double& x : truth.b) {
    b_sum += x;
    x *= rise;
  }
  truth.kappa0 = b_sum * u_max;
  for (std::size_t k = 0; k < truth.descending_v.size(); ++k) {
    truth.descending_u[k] = (descending(truth.descending_v[k]) - u_max) / rise;
  }
  for (std::size_t k = 0; k < truth.ascending_v.size(); ++k) {
    truth.ascending_u[k] = (ascending(truth.ascending_v[k]) - u_max) / rise;
  }
  truth.ok = true;
  return truth;
}

JointModel true_plant_on_tables(const ExperimentConfig& config, int border_segments, const std::vector<double>& a,
                                const std::vector<double>& b, const Border& ascending, const Border& descending) {
  const int segments = std::max(border_segments, 1);
  const detail::Layout layout = detail::make_layout(config, segments);
  JointModel tables;
  tables.n = config.n;
  tables.v_min = config.v_min;
  tables.v_max = config.v_max;
  tables.structure.border_segments = segments;
  tables.descending_v = layout.descending.x;
  tables.ascending_v = layout.ascending.x;
  tables.descending_u.assign(tables.descending_v.size(), 0.0);
  tables.ascending_u.assign(tables.ascending_v.size(), 0.0);
  return with_true_plant(tables, a, b, ascending, descending);
}

}  // namespace lashid::sim
