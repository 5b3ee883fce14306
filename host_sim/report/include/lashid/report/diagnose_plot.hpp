// The figure of `lashid diagnose --plot`.
#pragma once

#include <string>

#include "lashid/diagnose/diagnosis.hpp"

namespace lashid::report {

/// Measured vs nominal vs extended simulation on val, residual autocorrelation and input cross-correlation with
/// their 99 % bands, as one PNG (gnuplot). Throws DataError naming `png_path` when it cannot be written.
void plot_diagnosis(const sim::Diagnosis& diagnosis, const std::string& png_path);

}  // namespace lashid::report
