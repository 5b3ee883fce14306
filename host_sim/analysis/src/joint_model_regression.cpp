#include "joint_model_regression.hpp"

#include <algorithm>

namespace lashid::sim::detail {

RegressionShape regression_shape(int n, int P, const FlatRecording& data, const ModelStructure& structure) {
  RegressionShape g;
  g.n = n;
  g.P = P;
  g.cols = n + n * P + 1 + (structure.drift ? 1 : 0);
  for (std::size_t t = static_cast<std::size_t>(n); t < data.size(); ++t) {
    if (data.is_identification(t)) g.rows.push_back(t);
  }
  return g;
}

NormalEquations normal_equations(const RegressionShape& g, const FlatRecording& data, const ModelStructure& structure,
                                 const Basis& phi, const std::vector<double>* instruments_y) {
  NormalEquations ne;
  ne.zx = Eigen::MatrixXd::Zero(g.cols, g.cols);
  ne.zy = Eigen::VectorXd::Zero(g.cols);
  ne.energy = Eigen::VectorXd::Zero(g.cols);
  if (instruments_y == nullptr) {
    // Symmetric: each pair of a row's entries once, into the upper triangle, mirrored at the end (the entries'
    // columns are distinct within a row).
    visit_rows(g, data, structure, phi, nullptr, [&](std::size_t, const std::vector<Entry>& x, double y) {
      ne.yy += y * y;
      for (std::size_t p = 0; p < x.size(); ++p) {
        const Entry& a = x[p];
        ne.zy(a.column) += a.value * y;
        for (std::size_t q = p; q < x.size(); ++q) {
          const Entry& b = x[q];
          ne.zx(std::min(a.column, b.column), std::max(a.column, b.column)) += a.value * b.value;
        }
      }
    });
    ne.zx.triangularView<Eigen::StrictlyLower>() = ne.zx.transpose();
    ne.energy = ne.zx.diagonal();
    return ne;
  }
  // Instruments: the same row with the instruments' lags in the a_i columns (the first n entries of each lag group
  // are the y lags, in the same order in both visits).
  std::vector<std::vector<Entry>> z_rows;
  z_rows.reserve(g.rows.size());
  visit_rows(g, data, structure, phi, instruments_y,
             [&](std::size_t, const std::vector<Entry>& z, double) { z_rows.push_back(z); });
  std::size_t r = 0;
  visit_rows(g, data, structure, phi, nullptr, [&](std::size_t, const std::vector<Entry>& x, double y) {
    const std::vector<Entry>& z = z_rows[r++];
    for (const Entry& a : z) {
      ne.zy(a.column) += a.value * y;
      for (const Entry& b : x) ne.zx(a.column, b.column) += a.value * b.value;
    }
    for (const Entry& b : x) ne.energy(b.column) += b.value * b.value;
  });
  return ne;
}

}  // namespace lashid::sim::detail
