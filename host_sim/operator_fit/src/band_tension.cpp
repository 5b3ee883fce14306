// The friction-gap operator per band tension, interpolated in tension; the tension of a file from its name or an
// override.
#include "lashid/operator_fit/band_tension.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <stdexcept>

#include <fmt/format.h>

namespace lashid::sim {

namespace {

constexpr std::string_view kTensionMarker = "lbtension";

// The number that ends just before `end` in `name` (digits and '.'), or nullopt.
std::optional<double> number_before(std::string_view name, std::size_t end) {
  std::size_t begin = end;
  while (begin > 0 && (std::isdigit(static_cast<unsigned char>(name[begin - 1])) || name[begin - 1] == '.')) {
    --begin;
  }
  while (begin < end && name[begin] == '.') ++begin;  // "Hz.36" is not ".36"
  if (begin == end) return std::nullopt;
  double value = 0;
  const auto [ptr, ec] = std::from_chars(name.data() + begin, name.data() + end, value);
  if (ec != std::errc() || ptr != name.data() + end) return std::nullopt;
  return value;
}

// G of `table` on `points` equally spaced nodes of [-r, r] (values beyond the table's nodes are its end values).
std::vector<std::pair<double, double>> on_grid(const std::vector<std::pair<double, double>>& table, double r,
                                               int points) {
  const Border g = Border::from_table(table);
  std::vector<std::pair<double, double>> out;
  for (int i = 0; i < points; ++i) {
    const double e = -r + 2 * r * i / (points - 1);
    out.emplace_back(e, g(e));
  }
  return out;
}

}  // namespace

std::optional<double> tension_from_file_name(std::string_view path) {
  const std::string name = std::filesystem::path(path).filename().string();
  const std::size_t at = name.find(kTensionMarker);
  if (at == std::string::npos) return std::nullopt;
  return number_before(name, at);
}

TensionOverride parse_tension_override(std::string_view text) {
  const std::size_t eq = text.rfind('=');
  if (eq == std::string_view::npos || eq == 0) {
    throw std::invalid_argument(fmt::format("--tension '{}': expected FILE=LB, for example eq_KocaeliDBE.csv=36",
                                            text));
  }
  const std::string_view number = text.substr(eq + 1);
  double value = 0;
  const auto [ptr, ec] = std::from_chars(number.data(), number.data() + number.size(), value);
  if (number.empty() || ec != std::errc() || ptr != number.data() + number.size() || !std::isfinite(value) ||
      value < 0) {
    throw std::invalid_argument(fmt::format("--tension '{}': '{}' is not a band tension in lb (a number >= 0)", text,
                                            number));
  }
  return {std::string(text.substr(0, eq)), value};
}

std::optional<double> file_tension(const std::string& source, std::span<const TensionOverride> overrides) {
  const std::string base = std::filesystem::path(source).filename().string();
  for (const auto& o : overrides) {
    if (o.file == source || o.file == base) return o.tension_lb;
  }
  return tension_from_file_name(source);
}

TensionCurve TensionFrictionFit::at(double tension_lb) const {
  if (tensions.empty()) throw std::logic_error("TensionFrictionFit::at: no fitted tension");
  if (tensions.size() == 1) return tensions.front();
  std::size_t i = 0;  // segment [i, i + 1]: the one holding the tension, or the nearest end segment
  while (i + 2 < tensions.size() && tension_lb > tensions[i + 1].tension_lb) ++i;
  const TensionCurve& a = tensions[i];
  const TensionCurve& b = tensions[i + 1];
  const double w = (tension_lb - a.tension_lb) / (b.tension_lb - a.tension_lb);
  const double r = (1 - w) * a.half_width + w * b.half_width;
  if (!(r > 0) || !std::isfinite(2 * r) || a.curve.size() != b.curve.size()) {
    throw std::invalid_argument(fmt::format("the operator per band tension cannot be extrapolated to {:g} lb (play "
                                            "half-width {:g})",
                                            tension_lb, r));
  }
  TensionCurve out{tension_lb, r, {}, (1 - w) * a.stiffness + w * b.stiffness, 0, {}};
  const std::size_t nodes = a.curve.size();
  for (std::size_t n = 0; n < nodes; ++n) {
    const double e = -r + 2 * r * static_cast<double>(n) / static_cast<double>(nodes - 1);
    out.curve.emplace_back(e, (1 - w) * a.curve[n].second + w * b.curve[n].second);
    if (!std::isfinite(out.curve.back().second)) {
      throw std::invalid_argument(fmt::format("the operator per band tension cannot be extrapolated to {:g} lb (its "
                                              "force is not finite there)",
                                              tension_lb));
    }
  }
  if (!std::isfinite(out.stiffness)) {
    throw std::invalid_argument(
        fmt::format("the operator per band tension cannot be extrapolated to {:g} lb (stiffness not finite)",
                    tension_lb));
  }
  return out;
}

std::unique_ptr<FrictionGapOperator> TensionFrictionFit::make(double tension_lb) const {
  const TensionCurve c = at(tension_lb);
  return std::make_unique<FrictionGapOperator>(Border::from_table(c.curve), c.stiffness);
}

double TensionFrictionFit::plateau_slope(bool upper) const {
  double mt = 0, mg = 0;
  for (const auto& c : tensions) {
    mt += c.tension_lb / static_cast<double>(tensions.size());
    mg += (upper ? c.curve.back().second : c.curve.front().second) / static_cast<double>(tensions.size());
  }
  double num = 0, den = 0;
  for (const auto& c : tensions) {
    const double g = upper ? c.curve.back().second : c.curve.front().second;
    num += (c.tension_lb - mt) * (g - mg);
    den += (c.tension_lb - mt) * (c.tension_lb - mt);
  }
  return den > 0 ? num / den : 0.0;
}

bool TensionFrictionFit::extrapolates(double tension_lb) const {
  return tensions.empty() || tension_lb < tensions.front().tension_lb || tension_lb > tensions.back().tension_lb;
}

TensionFrictionFit fit_extended_by_tension(const std::vector<DamperRecord>& train, std::span<const double> tensions_lb,
                                           const OperatorFitOptions& options) {
  if (train.size() != tensions_lb.size()) {
    throw std::invalid_argument(fmt::format("fit_extended_by_tension: {} training records but {} tensions",
                                            train.size(), tensions_lb.size()));
  }
  std::map<double, std::vector<DamperRecord>> groups;
  for (std::size_t i = 0; i < train.size(); ++i) {
    if (!std::isfinite(tensions_lb[i]) || tensions_lb[i] < 0) {
      throw std::invalid_argument(fmt::format("{}: band tension {} lb is not a number >= 0", train[i].source,
                                              tensions_lb[i]));
    }
    groups[tensions_lb[i]].push_back(train[i]);
  }
  if (groups.size() < 2) {
    throw std::invalid_argument(fmt::format(
        "the tension model needs training files at two band tensions or more, all are at {} lb",
        groups.empty() ? 0.0 : groups.begin()->first));
  }
  TensionFrictionFit best;
  for (const auto& [tension, records] : groups) {
    // Each tension's operator is fitted exactly as fit_extended() fits one, on that tension's files.
    ExtendedFit fit = best_half_width(records, options);
    best.tensions.push_back(TensionCurve{tension, fit.half_width, on_grid(fit.curve, fit.half_width, options.points),
                                         fit.stiffness, records.size(), std::move(fit.train_error_by_width)});
  }
  double sum = 0;
  for (std::size_t i = 0; i < train.size(); ++i) {
    const auto op = best.make(tensions_lb[i]);
    sum += fit_to_record(train[i], simulate_operator(*op, train[i].v, train[i].u.front()));
  }
  best.fit_train = sum / static_cast<double>(train.size());
  return best;
}

std::string band_tension_in_words(const TensionFrictionFit& fit, const TestErrors& errors) {
  std::string levels;
  for (const auto& c : fit.tensions) {
    levels += fmt::format("{}{:g} lb: {:.2f} / {:.2f} (r = {:.2f})", levels.empty() ? "" : ", ", c.tension_lb,
                          c.curve.back().second, c.curve.front().second, c.half_width);
  }
  const double removed = errors.extended > 0 ? 1.0 - errors.with_dynamics / errors.extended : 0.0;
  return fmt::format(
      "the friction force scales with band tension: the upper plateau G(+r) by {:+.3f} and the lower G(-r) by "
      "{:+.3f} per lb (plateaus up / down at {}; identified on the training files only); with "
      "the friction level of each file's tension the squared error on the test files {} by {:.1f} % (mean test fit "
      "{:.1f} % -> {:.1f} %)",
      fit.plateau_slope(true), fit.plateau_slope(false), levels, removed >= 0 ? "drops" : "grows",
      100 * std::fabs(removed), errors.mean_fit_extended, errors.mean_fit_dynamics);
}

std::optional<DamperCause> friction_level_scales_with_band_tension(const TensionFrictionFit& fit,
                                                                   const TestErrors& errors,
                                                                   const DamperCauseOptions& options) {
  if (fit.tensions.size() < 2 || !(errors.extended > 0)) return std::nullopt;
  if (!(1.0 - errors.with_dynamics / errors.extended >= options.band_tension_error_reduction)) return std::nullopt;
  return DamperCause{"friction_level_scales_with_band_tension", true, band_tension_in_words(fit, errors)};
}

}  // namespace lashid::sim
