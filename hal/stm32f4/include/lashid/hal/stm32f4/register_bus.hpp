// The register access of the STM32F4 start-up sequences (clock_tree.hpp, usart_pins.hpp). On the chip it is the
// memory-mapped bus (MmioBus); on the PC, a test's model of the registers, so that the very sequences the image runs
// are checked against the reference manual's rules (tests/test_stm32f4_sequences.cpp). Freestanding: no heap, no I/O.
#pragma once

#include <concepts>
#include <cstdint>

namespace lashid::hal::stm32f4 {

/// A 32-bit register file: read(address) and write(address, value).
template <typename Bus>
concept RegisterBus = requires(Bus& bus, std::uintptr_t address, std::uint32_t value) {
  { bus.read(address) } -> std::same_as<std::uint32_t>;
  bus.write(address, value);
};

/// The chip's registers, through volatile accesses (one bus access per call, in program order).
struct MmioBus {
  std::uint32_t read(std::uintptr_t address) const { return *reinterpret_cast<volatile std::uint32_t*>(address); }
  void write(std::uintptr_t address, std::uint32_t value) const {
    *reinterpret_cast<volatile std::uint32_t*>(address) = value;
  }
};
static_assert(RegisterBus<MmioBus>);
static_assert(RegisterBus<const MmioBus>);

/// Polls `address` until (value & mask) == expected, at most `limit` reads. Returns whether it got there.
template <RegisterBus Bus>
bool wait_for_bits(Bus& bus, std::uintptr_t address, std::uint32_t mask, std::uint32_t expected, std::uint32_t limit) {
  for (std::uint32_t polls = 0; polls < limit; ++polls) {
    if ((bus.read(address) & mask) == expected) return true;
  }
  return false;
}

}  // namespace lashid::hal::stm32f4
