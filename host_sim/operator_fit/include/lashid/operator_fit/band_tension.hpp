// The friction damper's band tension as a model input (docs/friction-damper.md): the friction-gap operator fitted
// per band tension on the training files, and interpolated in tension for any other file.
//
// A band brake's friction force grows with the band tension. The model fits the friction-gap operator (r, G, k) per
// training tension T_i, exactly as fit_extended() on that tension's files. For a file at tension T, r, k and every
// node of G (on `points` equally spaced nodes of [-r, r], node n matched with node n) are linear in T between the
// two nearest training tensions, and extrapolated along the two nearest ones outside their range.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "lashid/io/damper_data.hpp"
#include "lashid/operator_fit/damper_causes.hpp"
#include "lashid/operator_fit/operator_fit.hpp"
#include "lashid/plant/friction_gap.hpp"

namespace lashid::sim {

/// The band tension (lb) written in a file name as `<T>lbtension` (e.g. char_0.5Hz36lbtension1amplitude.csv: 36),
/// looked for in the file's base name only. nullopt when the name has none.
std::optional<double> tension_from_file_name(std::string_view path);

/// One `--tension FILE=LB` override: FILE is matched against a record's source as given or its base name.
struct TensionOverride {
  std::string file;
  double tension_lb = 0;
};
/// Parses "FILE=LB". Throws std::invalid_argument (quoting the text) without '=', with an empty FILE, or with an
/// LB that is not a finite number >= 0.
TensionOverride parse_tension_override(std::string_view text);

/// The tension of a file: its override if one matches, else its name's. nullopt when neither gives one.
std::optional<double> file_tension(const std::string& source, std::span<const TensionOverride> overrides);

/// G and k of the friction-gap operator at one training tension.
struct TensionCurve {
  double tension_lb = 0;
  double half_width = 0;                         ///< r of the play at this tension
  std::vector<std::pair<double, double>> curve;  ///< G on equally spaced nodes of [-r, r]
  double stiffness = 0;                          ///< k
  std::size_t files = 0;                         ///< training files at this tension
  std::vector<std::pair<double, double>> train_error_by_width;  ///< (r, training RMS error) at this tension
};

struct TensionFrictionFit {
  std::vector<TensionCurve> tensions;  ///< one per training tension, increasing
  double fit_train = 0;                ///< mean training fit (%), each file simulated at its own tension

  /// r, k and G interpolated (or extrapolated) linearly in tension, node by node.
  TensionCurve at(double tension_lb) const;
  std::unique_ptr<FrictionGapOperator> make(double tension_lb) const;
  /// Least-squares slope over the training tensions of G(+r) (`upper` true) or G(-r) (force per lb).
  double plateau_slope(bool upper) const;
  /// True when `tension_lb` lies outside [lowest, highest] training tension.
  bool extrapolates(double tension_lb) const;
};

/// Fits the model on the training records, `tensions_lb[i]` being the band tension of train[i]. Per tension, for each
/// candidate r (candidate_half_widths()): G and k by fit_curve_at_width() on that tension's files; the r with the
/// least training squared error at that tension is kept. Throws std::invalid_argument when the sizes
/// differ, when there are fewer than two distinct tensions (naming the one found), or for a tension that is not
/// finite and >= 0 (naming the file).
TensionFrictionFit fit_extended_by_tension(const std::vector<DamperRecord>& train, std::span<const double> tensions_lb,
                                           const OperatorFitOptions& options);

/// The friction level against the band tension in words: G(+r) and G(-r) at each training tension, their slopes
/// (force per lb) and, for the squared errors of the tension-blind and the tension model summed over the test files
/// (and their mean test fits), how much of the error the tension removes.
std::string band_tension_in_words(const TensionFrictionFit& fit, const TestErrors& errors);

/// friction_level_scales_with_band_tension: named when the tension model (`errors.with_dynamics` standing for its
/// squared error, `errors.extended` for the tension-blind operator's) removes at least
/// options.band_tension_error_reduction of the squared error on the test files; the evidence is
/// band_tension_in_words(). Otherwise nothing.
std::optional<DamperCause> friction_level_scales_with_band_tension(const TensionFrictionFit& fit,
                                                                   const TestErrors& errors,
                                                                   const DamperCauseOptions& options = {});

}  // namespace lashid::sim
