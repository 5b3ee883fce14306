// What the commands that read a plant file (simulate --plant, hil --plant) tell the user about it.
#pragma once

#include <string>
#include <string_view>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "lashid/io/plant_file.hpp"

namespace lashid::app {

// Unknown keys are allowed (a name, notes), but a misspelt optional key would otherwise vanish without a word.
inline void note_ignored_keys(const sim::PlantSpec& spec, std::string_view plant_name) {
  for (const std::string& key : spec.ignored_keys) {
    fmt::print(stderr, "lashid: note: {}: key '{}' is not a plant-file key; ignored\n", plant_name, key);
  }
}

// One line for the recording's comments: the plant's structure and its effects.
inline std::string plant_summary(const sim::PlantSpec& spec) {
  std::string text = fmt::format("plant: {}, {} border points on [{}, {}], a = [{}], b = [{}], equation noise std {}",
                                 sim::to_string(spec.op), spec.border_v.size(), spec.border_v.front(),
                                 spec.border_v.back(), fmt::join(spec.a, ", "), fmt::join(spec.b, ", "),
                                 spec.equation_noise_std);
  if (spec.sensor_noise) {
    text += fmt::format(", sensor noise std {} pole {}", spec.sensor_noise->std, spec.sensor_noise->pole);
  }
  if (spec.input_lag > 0) text += fmt::format(", input lag {}", spec.input_lag);
  if (spec.dead_time > 0) text += fmt::format(", dead time {}", spec.dead_time);
  if (spec.sensor_drift_per_sample != 0) {
    text += fmt::format(", sensor drift {} per sample", spec.sensor_drift_per_sample);
  }
  return text;
}

}  // namespace lashid::app
