// The mps2 peripheral registers used by the board support (private to hal/mps2): the CMSDK APB UART as QEMU models
// it (hw/char/cmsdk-apb-uart.c register layout: DATA, STATE, CTRL, INTSTATUS/INTCLEAR, BAUDDIV). The core's registers
// (SCB, SysTick, FPU) are hal/cortex_m's.
#pragma once

#include <cstdint>

namespace lashid::hal::mps2::detail {

inline volatile std::uint32_t& reg(std::uintptr_t address) {
  return *reinterpret_cast<volatile std::uint32_t*>(address);
}

// CMSDK APB UART (offsets)
inline constexpr std::uintptr_t kUartData = 0x00;
inline constexpr std::uintptr_t kUartState = 0x04;  // [0] TX full, [1] RX full, [2] TX overrun, [3] RX overrun (W1C)
inline constexpr std::uintptr_t kUartCtrl = 0x08;   // [0] TX enable, [1] RX enable, [2..5] interrupt enables
inline constexpr std::uintptr_t kUartIntStatus = 0x0C;  // write 1 to clear
inline constexpr std::uintptr_t kUartBaudDiv = 0x10;    // >= 16
inline constexpr std::uint32_t kUartTxFull = 1U << 0;
inline constexpr std::uint32_t kUartRxFull = 1U << 1;
inline constexpr std::uint32_t kUartTxOverrun = 1U << 2;
inline constexpr std::uint32_t kUartRxOverrun = 1U << 3;
inline constexpr std::uint32_t kUartTxEnable = 1U << 0;
inline constexpr std::uint32_t kUartRxEnable = 1U << 1;
inline constexpr std::uint32_t kUartRxIntEnable = 1U << 3;  // CTRL: RX interrupt when a byte arrives
inline constexpr std::uint32_t kUartIntRx = 1U << 1;        // INTSTATUS/INTCLEAR: the RX interrupt

}  // namespace lashid::hal::mps2::detail
