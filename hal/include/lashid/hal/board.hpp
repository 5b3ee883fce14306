// The firmware's only door to hardware, as a C++20 concept: the same firmware code builds against the host board
// (in-process simulator) and the Cortex-M boards (QEMU mps2), with no virtual calls. A board is chosen with
//   static_assert(lashid::hal::Board<MyBoard>);
#pragma once

#include <concepts>
#include <cstddef>
#include <cstdint>

#include "lashid/hal/status.hpp"

namespace lashid::hal {

template <class B>
concept Board = requires(B& board, const B& const_board, float v, float& y, std::uint8_t& byte,
                         const std::uint8_t* data, std::size_t size) {
  /// Applies the actuator command v(t) of the current sample.
  /// kOk; kOutOfRange (outside the actuator's range: not applied); kLinkError / kTimeout (remote actuator).
  { board.actuate(v) } -> std::same_as<Status>;

  /// Measures the output y(t) of the current sample (called after actuate()). y(t) is the output at the sample
  /// instant, which v(t) has not reached (the model has no direct feedthrough, b_0 = 0): a board that converts a
  /// physical signal samples it before it applies v(t) (the STM32F4 analog board: sample_then_actuate).
  /// kOk; kOutOfRange (a value, but not usable: non-finite or outside the sensor's range; the sequencer counts the
  /// sample as bad, estimates without it and goes on); kSensorFault (no measurement for this sample: the run ends
  /// with a sensor fault, so a glitch that still gives a sample must be kOutOfRange); kTimeout (ends the run like
  /// kSensorFault); kStopped (the run ends, stopped).
  { board.measure(y) } -> std::same_as<Status>;

  /// Sample clock: returns at the next sample instant.
  /// kOk; kTimeout when the previous sample overran its period (the sample is late, not skipped).
  { board.wait_for_sample_tick() } -> std::same_as<Status>;

  /// Byte link for commands and reports: writes all `size` bytes. kOk; kLinkError; kTimeout.
  { board.link_write(data, size) } -> std::same_as<Status>;

  /// Byte link, non-blocking read of one byte. kOk; kWouldBlock (none pending); kLinkError (overrun: bytes lost),
  /// reported once and cleared: the next call reads on (the firmware reads at most a bounded number of bytes or
  /// errors per poll, so a sticky error costs link errors, not the sample clock).
  { board.link_read(byte) } -> std::same_as<Status>;

  /// Monotonic cycle/tick counter, wrapping at 2^32 (differences are valid across one wrap).
  { const_board.cycles() } -> std::same_as<std::uint32_t>;
};

// Optional board extensions, named so that a board that has one can say so where it is chosen
// (static_assert(hal::ReportsStackUse<MyBoard>)): a misspelt member then fails to compile instead of silently
// dropping the figure from the firmware's cost report.

/// The stack's high-water mark in bytes since reset (e.g. from a painted stack).
template <class B>
concept ReportsStackUse = requires(const B& board) {
  { board.stack_high_water_bytes() } -> std::convertible_to<std::size_t>;
};

/// Counts of failed and of retried plant exchanges since reset (a remote actuator and sensor behind a link).
template <class B>
concept ReportsExchangeErrors = requires(const B& board) {
  { board.exchange_errors() } -> std::convertible_to<std::uint32_t>;
  { board.exchange_retries() } -> std::convertible_to<std::uint32_t>;
};

/// The actuator's range in the design's units (what a DAC reaches, through the board's scaling): the firmware
/// refuses a design whose working interval [v_min, v_max] reaches beyond it (DesignStatus::kOutsideActuatorRange)
/// instead of ending the run at its first out-of-range command.
template <class B>
concept LimitsActuatorRange = requires(const B& board) {
  { board.actuator_low() } -> std::convertible_to<float>;
  { board.actuator_high() } -> std::convertible_to<float>;
};

/// link_write queues its bytes and returns without waiting for the wire (an interrupt- or DMA-driven transmitter, or
/// memory), and the link carries a stream of every sample at the board's sample rate (9 bytes a sample): the firmware
/// may then stream them (kStartStreamSamples) without delaying the sample clock. A board whose link_write waits for
/// each byte, or whose link is too slow for its rate, does not model it, and never streams.
template <class B>
concept BuffersLinkWrites = B::kBuffersLinkWrites;

/// The rate of cycles() in cycles per second, known at compile time: lets the firmware bound waits in time (the
/// hold of its reports after a run) without a clock of its own.
template <class B>
concept KnowsCycleRate = requires {
  { B::kCyclesPerSecond } -> std::convertible_to<std::uint32_t>;
};

}  // namespace lashid::hal
