// Memory-mapped registers used by the mps2 board support (private to hal/mps2).
// Addresses: ARMv7-M Architecture Reference Manual (System Control Space, SysTick, FP extension) and the CMSDK APB UART
// as QEMU models it (hw/char/cmsdk-apb-uart.c register layout: DATA, STATE, CTRL, INTSTATUS/INTCLEAR, BAUDDIV).
#pragma once

#include <cstdint>

namespace lashid::hal::mps2::detail {

inline volatile std::uint32_t& reg(std::uintptr_t address) {
  return *reinterpret_cast<volatile std::uint32_t*>(address);
}

// System Control Block
inline constexpr std::uintptr_t kCpuid = 0xE000'ED00;  // [15:4] PartNo
inline constexpr std::uintptr_t kIcsr = 0xE000'ED04;   // [26] PENDSTSET, [8:0] VECTACTIVE
inline constexpr std::uintptr_t kVtor = 0xE000'ED08;
inline constexpr std::uintptr_t kCfsr = 0xE000'ED28;   // UsageFault/BusFault/MemManage status
inline constexpr std::uintptr_t kHfsr = 0xE000'ED2C;
inline constexpr std::uintptr_t kMmfar = 0xE000'ED34;
inline constexpr std::uintptr_t kBfar = 0xE000'ED38;
inline constexpr std::uintptr_t kCpacr = 0xE000'ED88;  // [23:20] CP11, CP10 access
inline constexpr std::uintptr_t kMvfr0 = 0xE000'EF40;
inline constexpr std::uint32_t kIcsrPendStSet = 1U << 26;
inline constexpr std::uint32_t kCpacrCp10Cp11Full = 0xFU << 20;

// SysTick
inline constexpr std::uintptr_t kSystCsr = 0xE000'E010;  // [0] ENABLE, [1] TICKINT, [2] CLKSOURCE (1 = CPU), [16] COUNTFLAG
inline constexpr std::uintptr_t kSystRvr = 0xE000'E014;
inline constexpr std::uintptr_t kSystCvr = 0xE000'E018;
inline constexpr std::uint32_t kSystEnable = 1U << 0;
inline constexpr std::uint32_t kSystTickInt = 1U << 1;
inline constexpr std::uint32_t kSystClkSourceCpu = 1U << 2;

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

}  // namespace lashid::hal::mps2::detail
