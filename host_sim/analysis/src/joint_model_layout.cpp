#include "joint_model_layout.hpp"

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <utility>

#include "lashid/plant/nearby_search.hpp"
#include "lashid/plant/operators.hpp"
#include "model_operator.hpp"

namespace lashid::sim::detail {

namespace {

// One stencil per interior node; those of the experiment's abscissas apply only where the data do not reach the
// node (otherwise the data decide, and a real border may have a kink there).
void add_stencils(const BorderLayout& border, std::vector<SmoothnessStencil>& stencils) {
  for (std::size_t k = 1; k + 1 < border.x.size(); ++k) {
    if (border.param[k] < 0) continue;
    const double span = border.x[k + 1] - border.x[k - 1];
    stencils.push_back({border.param[k - 1], border.param[k], border.param[k + 1],
                        (border.x[k + 1] - border.x[k]) / span, (border.x[k] - border.x[k - 1]) / span});
  }
}

// Splits every interval of `border` into `segments` equal parts; the new points get new parameters.
void subdivide(BorderLayout& border, int segments, int& parameters) {
  BorderLayout fine;
  for (std::size_t k = 0; k < border.x.size(); ++k) {
    if (k > 0) {
      for (int j = 1; j < segments; ++j) {
        fine.x.push_back(border.x[k - 1] + (border.x[k] - border.x[k - 1]) * j / segments);
        fine.param.push_back(parameters++);
      }
    }
    fine.x.push_back(border.x[k]);
    fine.param.push_back(border.param[k]);
  }
  border = std::move(fine);
}

}  // namespace

HatRow hat_row(const BorderLayout& border, double w) {
  std::size_t hint = border.x.size() / 2;
  return hat_row(border, w, hint);
}

HatRow hat_row(const BorderLayout& border, double w, std::size_t& hint) {
  const auto& x = border.x;
  w = std::clamp(w, x.front(), x.back());
  std::size_t k = upper_bound_near(x, w, hint);
  k = std::clamp<std::size_t>(k, 1, x.size() - 1) - 1;
  const double s = (w - x[k]) / (x[k + 1] - x[k]);
  HatRow row;
  row.param = {border.param[k], border.param[k + 1]};
  row.weight = {border.param[k] >= 0 ? 1.0 - s : 0.0, border.param[k + 1] >= 0 ? s : 0.0};
  return row;
}

Layout make_layout(const ExperimentConfig& c, int segments) {
  if (c.V_d.size() != static_cast<std::size_t>(c.m) || c.V_a.size() != static_cast<std::size_t>(c.m)) {
    throw std::invalid_argument("the joint model needs both schemes: V_d and V_a with m points each");
  }
  const int m = c.m;
  Layout l;
  for (int j = 0; j < m; ++j) {
    l.descending.x.push_back(c.V_d[static_cast<std::size_t>(j)]);
    l.descending.param.push_back(j);
  }
  l.descending.x.push_back(c.v_max);
  l.descending.param.push_back(-1);
  l.ascending.x.push_back(c.v_min);
  l.ascending.param.push_back(0);  // C_a(v_min) = C_d(v_min) = u_m
  for (int j = m - 1; j >= 0; --j) {
    l.ascending.x.push_back(c.V_a[static_cast<std::size_t>(j)]);
    l.ascending.param.push_back(j == 0 ? -1 : m - 1 + j);
  }
  l.parameters = 2 * m - 1;
  l.level_parameters = l.parameters;
  if (segments > 1) {
    subdivide(l.descending, segments, l.parameters);
    subdivide(l.ascending, segments, l.parameters);
  }
  add_stencils(l.descending, l.stencils);
  add_stencils(l.ascending, l.stencils);
  return l;
}

Eigen::VectorXd border_parameters(const JointModel& model, const Layout& layout) {
  Eigen::VectorXd c = Eigen::VectorXd::Zero(layout.parameters);
  for (const auto* border : {&layout.descending, &layout.ascending}) {
    const auto& u = border == &layout.descending ? model.descending_u : model.ascending_u;
    for (std::size_t k = 0; k < border->param.size(); ++k) {
      if (border->param[k] >= 0) c(border->param[k]) = u[k];
    }
  }
  return c;
}

Basis operator_basis(const Layout& layout, const std::vector<double>& w, OperatorKind op,
                               const JointModel* current) {
  const std::size_t T = w.size();
  Basis phi(T);
  std::unique_ptr<HysteresisOperator> model_op;
  if (op == OperatorKind::kBacklash && current != nullptr) model_op = make_model_operator(*current, w[0]);
  double u_prev = model_op ? model_op->step(w[0]) : 0.0;
  // Each border's lookups start where its last one ended: w moves a segment or less per sample.
  std::size_t ascending_hint = 0, descending_hint = 0;
  phi[0] = hat_row(layout.descending, w[0], descending_hint);
  for (std::size_t t = 1; t < T; ++t) {
    bool hold = w[t] == w[t - 1];
    if (model_op) {
      const double u = model_op->step(w[t]);
      hold = hold || u == u_prev;
      u_prev = u;
    }
    if (hold) {
      phi[t] = phi[t - 1];
    } else if (w[t] > w[t - 1]) {
      phi[t] = hat_row(layout.ascending, w[t], ascending_hint);
    } else {
      phi[t] = hat_row(layout.descending, w[t], descending_hint);
    }
  }
  return phi;
}

// A backlash behind an input lag is given non-negative play: C~_a <= C~_d at every point of the finer tables
// (C~_a lowered to C~_d where it is above, C~_d raised to C~_a). In the scaling of (3.11c), where u~ rises from -1
// at v_min to 0 at v_max whatever the sign of the plant's gain, that is the backlash whose output lags its input.
// Why: the finer tables' points are fitted for given regimes, and nothing in that fit keeps the borders from
// crossing where the data are thin. Where they cross (most often beside v_max or v_min, where the borders meet),
// the model's own backlash can hold for good: risen on C~_a to a level that C~_d reaches only at a larger input,
// it never moves down again, and a lagged input never reaches the end point exactly. On the tuning seeds the
// true-lag fits of most missed backlashes did that, and their val simulation sat at one level (fit -75 to -110 %).
// The paper allows crossing borders (its Fig. 4); the nominal model, on the experiment's abscissas, still does.
void give_non_negative_play(JointModel& model) {
  const Border ascending = table_border(model.ascending_v, model.ascending_u);
  const Border descending = table_border(model.descending_v, model.descending_u);
  for (std::size_t i = 0; i < model.ascending_u.size(); ++i) {
    model.ascending_u[i] = std::min(model.ascending_u[i], descending(model.ascending_v[i]));
  }
  for (std::size_t i = 0; i < model.descending_u.size(); ++i) {
    model.descending_u[i] = std::max(model.descending_u[i], ascending(model.descending_v[i]));
  }
}

}  // namespace lashid::sim::detail
