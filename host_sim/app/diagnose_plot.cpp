// --plot of `lashid diagnose`.
#include <stdexcept>

#include "commands.hpp"
#include "lashid/sim/diagnosis.hpp"

namespace lashid::app {

void plot_diagnosis(const sim::Diagnosis& /*diagnosis*/, const std::string& /*png_path*/) {
  throw std::runtime_error("--plot is not available yet");
}

}  // namespace lashid::app
