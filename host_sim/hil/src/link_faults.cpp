#include "lashid/hil/link_faults.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace lashid::sim {

ByteFaults::ByteFaults(double rate, std::uint64_t seed, std::uint64_t stream)
    // One generator per direction, its seed a mix of the seed and the stream (distinct for distinct pairs).
    : rate_(rate), random_(seed * 4U + stream) {
  if (!(rate >= 0.0 && rate <= 1.0)) {
    throw std::invalid_argument(fmt::format("fault rate {} must be a probability in [0, 1]", rate));
  }
}

void ByteFaults::pass(const std::uint8_t* data, std::size_t size, std::vector<std::uint8_t>& out) {
  // Integer draws (not std::uniform_real_distribution, whose results differ between standard libraries): a fault
  // when a 53-bit uniform falls below rate * 2^53, then one of the three kinds with equal chance.
  const auto threshold = static_cast<std::uint64_t>(std::ldexp(rate_, 53));
  for (std::size_t i = 0; i < size; ++i) {
    ++counts_.bytes;
    const std::uint8_t byte = data[i];
    if ((random_() >> 11U) >= threshold) {
      out.push_back(byte);
      continue;
    }
    const std::uint64_t draw = random_();
    switch (draw % 3U) {
      case 0: ++counts_.dropped; break;
      case 1:
        ++counts_.flipped;
        out.push_back(static_cast<std::uint8_t>(byte ^ (1U << ((draw / 3U) % 8U))));
        break;
      default:
        ++counts_.duplicated;
        out.push_back(byte);
        out.push_back(byte);
        break;
    }
  }
}

FaultyLine::FaultyLine(double rate, std::uint64_t seed, std::uint64_t stream) {
  if (rate > 0) faults_.emplace(rate, seed, stream);
}

std::vector<std::uint8_t> FaultyLine::pass(const std::uint8_t* data, std::size_t size) {
  if (!faults_) return {data, data + size};
  std::vector<std::uint8_t> out;
  faults_->pass(data, size, out);
  return out;
}

}  // namespace lashid::sim
