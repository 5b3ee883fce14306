// The core's memory-mapped registers used by the Cortex-M support (private to hal/cortex_m).
// Addresses: ARMv7-M Architecture Reference Manual (System Control Space, SysTick, FP extension); the same on every
// Cortex-M3/M4/M7, whatever the vendor.
#pragma once

#include <cstdint>

namespace lashid::hal::cortex_m::detail {

inline volatile std::uint32_t& reg(std::uintptr_t address) {
  return *reinterpret_cast<volatile std::uint32_t*>(address);
}

// NVIC
inline constexpr std::uintptr_t kNvicIser = 0xE000'E100;  // NVIC_ISER0; ISERn at +4n
inline constexpr std::uintptr_t kNvicIcer = 0xE000'E180;  // NVIC_ICER0; ICERn at +4n
inline constexpr std::uintptr_t kNvicIspr = 0xE000'E200;  // NVIC_ISPR0; ISPRn at +4n
inline constexpr std::uintptr_t kNvicIcpr = 0xE000'E280;  // NVIC_ICPR0; ICPRn at +4n
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
inline constexpr std::uint32_t kCfsrMmarValid = 1U << 7;   // MMFAR holds the MemManage fault's address
inline constexpr std::uint32_t kCfsrBfarValid = 1U << 15;  // BFAR holds the BusFault's address
inline constexpr std::uint32_t kCfsrNoCp = 1U << 19;       // UsageFault NOCP: a coprocessor (FPU) access while disabled
inline constexpr std::uint32_t kCpacrCp10Cp11Full = 0xFU << 20;

// MPU (PMSAv7: ARMv7-M ARM B3.5)
inline constexpr std::uintptr_t kMpuType = 0xE000'ED90;  // [15:8] DREGION: number of data regions (0: no MPU)
inline constexpr std::uintptr_t kMpuCtrl = 0xE000'ED94;  // [0] ENABLE, [1] HFNMIENA, [2] PRIVDEFENA
inline constexpr std::uintptr_t kMpuRnr = 0xE000'ED98;   // region number
inline constexpr std::uintptr_t kMpuRbar = 0xE000'ED9C;  // [31:5] ADDR (aligned to the region's size)
inline constexpr std::uintptr_t kMpuRasr = 0xE000'EDA0;  // [28] XN, [26:24] AP, [5:1] SIZE (2^(SIZE+1) B), [0] ENABLE
inline constexpr std::uint32_t kMpuCtrlEnable = 1U << 0;
inline constexpr std::uint32_t kMpuCtrlPrivDefEna = 1U << 2;
inline constexpr std::uint32_t kMpuRasrXn = 1U << 28;
inline constexpr std::uint32_t kMpuRasrEnable = 1U << 0;

// SysTick
inline constexpr std::uintptr_t kSystCsr = 0xE000'E010;  // [0] ENABLE, [1] TICKINT, [2] CLKSOURCE (1 = CPU), [16] COUNTFLAG
inline constexpr std::uintptr_t kSystRvr = 0xE000'E014;
inline constexpr std::uintptr_t kSystCvr = 0xE000'E018;
inline constexpr std::uint32_t kSystEnable = 1U << 0;
inline constexpr std::uint32_t kSystTickInt = 1U << 1;
inline constexpr std::uint32_t kSystClkSourceCpu = 1U << 2;

}  // namespace lashid::hal::cortex_m::detail
