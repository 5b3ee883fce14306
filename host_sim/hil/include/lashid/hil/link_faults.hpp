// Random byte faults on a link, as a real serial line makes them: each byte passing through is, with probability
// `rate`, dropped, garbled (one random bit flipped) or duplicated (each a third of the faults). `lashid hil
// --fault-rate P --fault-seed S` puts one of these on each direction of both UARTs, so that the protocol's checks
// and retries (hal/link_protocol.hpp, hal/remote_plant_port.hpp, the host session) are exercised by chance, not by
// a schedule. Deterministic for a seed and a byte sequence; the draws of each direction are independent.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

namespace lashid::sim {

struct FaultCounts {
  std::uint64_t dropped = 0;
  std::uint64_t flipped = 0;
  std::uint64_t duplicated = 0;
  std::uint64_t bytes = 0;  ///< bytes that passed through (faulty or not)
  std::uint64_t injected() const { return dropped + flipped + duplicated; }
  FaultCounts& operator+=(const FaultCounts& o) {
    dropped += o.dropped;
    flipped += o.flipped;
    duplicated += o.duplicated;
    bytes += o.bytes;
    return *this;
  }
};

class ByteFaults {
 public:
  /// rate in [0, 1]; `stream` tells apart the directions that share a seed. Throws std::invalid_argument for a
  /// rate outside [0, 1] or NaN.
  ByteFaults(double rate, std::uint64_t seed, std::uint64_t stream);

  /// Appends `data` to `out` as the faulty line delivers it.
  void pass(const std::uint8_t* data, std::size_t size, std::vector<std::uint8_t>& out);
  const FaultCounts& counts() const { return counts_; }

 private:
  double rate_;
  std::mt19937_64 random_;
  FaultCounts counts_;
};

/// One direction of one UART: the bytes as they cross, through ByteFaults when the rate is above 0, untouched
/// (and not counted) otherwise.
class FaultyLine {
 public:
  FaultyLine(double rate, std::uint64_t seed, std::uint64_t stream);
  std::vector<std::uint8_t> pass(const std::uint8_t* data, std::size_t size);
  FaultCounts counts() const { return faults_ ? faults_->counts() : FaultCounts{}; }

 private:
  std::optional<ByteFaults> faults_;
};

}  // namespace lashid::sim
