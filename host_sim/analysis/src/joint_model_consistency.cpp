#include "joint_model_consistency.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>

#include "lashid/plant/border.hpp"
#include "lashid/plant/operators.hpp"
#include "model_operator.hpp"

namespace lashid::sim::detail {

void add_consistency_rows(const ConsistencyRows& rows, int n, int P, NormalEquations& ne) {
  for (const ConsistencyRow& r : rows) {
    for (int i = 0; i < n; ++i) {
      std::array<std::pair<Eigen::Index, double>, 5> e{};
      std::size_t k = 0;
      for (std::size_t j = 0; j < 4; ++j) {
        if (r.param[j] >= 0 && r.weight[j] != 0) e[k++] = {n + i * P + r.param[j], r.weight[j]};
      }
      if (r.target != 0) e[k++] = {n + i * P, r.target};  // - target b_i = + target theta_{i,0}
      for (std::size_t x = 0; x < k; ++x) {
        for (std::size_t y = 0; y < k; ++y) {
          ne.zx(e[x].first, e[y].first) += kConsistencyWeight * e[x].second * e[y].second;
        }
      }
    }
  }
}

namespace {

// A model's borders as its backlash runs them, and its border values c for hat rows.
struct ModelBorders {
  std::unique_ptr<HysteresisOperator> op;
  const BacklashOperator* backlash = nullptr;
  Eigen::VectorXd c;

  ModelBorders(const JointModel& model, const Layout& layout, double w0)
      : op(make_model_operator(model, w0)),
        backlash(dynamic_cast<const BacklashOperator*>(op.get())),
        c(border_parameters(model, layout)) {}
  double value(const HatRow& h) const { return hat_value(h, c); }
  const Border& border(int dir) const { return dir > 0 ? backlash->ascending() : backlash->descending(); }
};

bool strictly_inside(double x, double a, double b) { return x > std::min(a, b) && x < std::max(a, b); }

}  // namespace

int regime_violations(const Layout& layout, const std::vector<double>& w, const FlatRecording& data,
                      const Basis& phi, const JointModel* source, const JointModel& model,
                      const std::vector<char>& sticky, std::vector<char>& used, ConsistencyRows& rows) {
  if (w.empty()) return 0;
  ModelBorders own(model, layout, w[0]);
  if (own.backlash == nullptr) return 0;  // a switch's regimes do not depend on its borders
  std::unique_ptr<ModelBorders> from;
  if (source != nullptr && source->ok && source->structure.op == OperatorKind::kBacklash) {
    from = std::make_unique<ModelBorders>(*source, layout, w[0]);
  }
  int violated = 0;
  // The model's backlash follows phi: stepped on, and put back in phi's state wherever it leaves it (after a move,
  // exactly on the border, so that it knows it is on it).
  own.op->step(w[0]);
  for (std::size_t t = 1; t < w.size(); ++t) {
    const int dir = w[t] > w[t - 1] ? 1 : -1;
    const BorderLayout& table = dir > 0 ? layout.ascending : layout.descending;
    const Border& border = own.border(dir);
    const bool hold = phi[t] == phi[t - 1];
    const double level = own.value(phi[t - 1]);
    const double expected = own.value(phi[t]);
    const double stepped = own.op->step(w[t]);
    const bool broken = std::abs(stepped - expected) > 1e-9 * (1.0 + std::abs(expected));
    if (broken) own.op->reset(w[t], hold || w[t] == w[t - 1] ? expected : border(w[t]));
    if (w[t] == w[t - 1] || !data.is_identification(t)) continue;
    violated += broken;
    if (!broken && !sticky[t]) continue;
    // The side the border starts on: from the model phi came from (its geometry made the regimes), or a backlash's
    // usual one (C_a below the held level, C_d above) for the switch's regimes.
    double side = -dir;
    double source_level = 0;
    if (from) {
      source_level = from->value(phi[t - 1]);
      const double d0 = from->border(dir)(w[t - 1]) - source_level;
      side = d0 > 0 ? 1.0 : d0 < 0 ? -1.0 : 0.0;
    }
    if (side == 0) continue;
    const auto push = [&](double at, double target) {
      const HatRow h = hat_row(table, at);
      ConsistencyRow r;
      r.param = {h.param[0], h.param[1], phi[t - 1].param[0], phi[t - 1].param[1]};
      r.weight = {side * h.weight[0], side * h.weight[1], -side * phi[t - 1].weight[0],
                  -side * phi[t - 1].weight[1]};
      r.target = target;
      rows.push_back(r);
      used[t] = 1;
    };
    const auto on_side = [&](double at) { return side * (border(at) - level); };  // > 0: not crossed
    if (hold) {
      if (on_side(w[t]) < kConsistencyMargin) push(w[t], kConsistencyMargin);
      for (double x : table.x) {
        if (strictly_inside(x, w[t - 1], w[t]) && on_side(x) < kConsistencyMargin) push(x, kConsistencyMargin);
      }
      continue;
    }
    // Where the border crosses: w(t), or the first node inside the step where the source's border has crossed (a
    // border can cross and come back within one step).
    double witness = w[t];
    if (from && side * (from->border(dir)(w[t]) - source_level) > 0) {
      const std::size_t count = table.x.size();
      for (std::size_t i = 0; i < count; ++i) {
        const double x = table.x[dir > 0 ? i : count - 1 - i];
        if (strictly_inside(x, w[t - 1], w[t]) && side * (from->border(dir)(x) - source_level) <= 0) {
          witness = x;
          break;
        }
      }
    }
    if (on_side(witness) > -kConsistencyMargin) push(witness, -kConsistencyMargin);
  }
  return violated;
}

}  // namespace lashid::sim::detail
