// STM32F4 peripheral registers used by the board support (private to hal/stm32f4). Offsets and bits from RM0090
// (rev 19) 30.6 (USART registers); the RCC enable registers are named in lashid/hal/stm32f4.hpp (UsartPort). The
// core's registers (SCB, SysTick, FPU) are hal/cortex_m's.
#pragma once

#include <cstdint>

namespace lashid::hal::stm32f4::detail {

inline volatile std::uint32_t& reg(std::uintptr_t address) {
  return *reinterpret_cast<volatile std::uint32_t*>(address);
}

// USART (offsets, RM0090 30.6.1-30.6.4)
inline constexpr std::uintptr_t kUsartSr = 0x00;   // status
inline constexpr std::uintptr_t kUsartDr = 0x04;   // data (a read clears RXNE)
inline constexpr std::uintptr_t kUsartBrr = 0x08;  // [15:4] DIV_Mantissa, [3:0] DIV_Fraction
inline constexpr std::uintptr_t kUsartCr1 = 0x0C;
inline constexpr std::uintptr_t kUsartCr2 = 0x10;  // [13:12] STOP: 00 = 1 stop bit
inline constexpr std::uintptr_t kUsartCr3 = 0x14;  // flow control, DMA: all off
// SR bits (30.6.1)
inline constexpr std::uint32_t kSrPe = 1U << 0;    // parity error
inline constexpr std::uint32_t kSrFe = 1U << 1;    // framing error
inline constexpr std::uint32_t kSrNf = 1U << 2;    // noise detected
inline constexpr std::uint32_t kSrOre = 1U << 3;   // overrun: a byte arrived while RXNE was set, it was lost
inline constexpr std::uint32_t kSrRxne = 1U << 5;  // read data register not empty
inline constexpr std::uint32_t kSrTc = 1U << 6;    // transmission complete: the last byte has left the line
inline constexpr std::uint32_t kSrTxe = 1U << 7;   // transmit data register empty
// The receive errors: cleared, with the byte in DR, by reading SR then DR.
inline constexpr std::uint32_t kSrRxErrors = kSrOre | kSrFe | kSrNf | kSrPe;
// CR1 bits (30.6.4); M = 0 (8 data bits), OVER8 = 0 (16x oversampling), PCE = 0 (no parity)
inline constexpr std::uint32_t kCr1Re = 1U << 2;
inline constexpr std::uint32_t kCr1Rxneie = 1U << 5;  // interrupt on RXNE or ORE
inline constexpr std::uint32_t kCr1Txeie = 1U << 7;   // interrupt on TXE
inline constexpr std::uint32_t kCr1Te = 1U << 3;
inline constexpr std::uint32_t kCr1Ue = 1U << 13;

}  // namespace lashid::hal::stm32f4::detail
