// The pins of a USART: its TX and RX as alternate-function pins of a GPIO port (RM0090 rev 19, 8.3.7 and 8.4;
// the STM32F405 datasheet DS8626, Table 9, for the alternate function numbers). Without this the USART works but
// its signals never reach the pins. QEMU 7.2 does not model the GPIOs (writes ignored), so there it is harmless.
// Freestanding, no heap; on any RegisterBus (register_bus.hpp) so that the sequence is tested on the PC.
#pragma once

#include <cstdint>
#include <initializer_list>

#include "lashid/hal/stm32f4/register_bus.hpp"

namespace lashid::hal::stm32f4 {

/// A USART's TX and RX pins on one GPIO port, and the RCC_AHB1ENR bit that clocks that port (7.3.10).
struct UsartPins {
  std::uintptr_t gpio_base;
  std::uint32_t rcc_ahb1enr_bit;
  std::uint32_t tx_pin, rx_pin;       ///< 0..15
  std::uint32_t alternate_function;   ///< AF0..AF15
};

namespace pin_registers {
inline constexpr std::uintptr_t kRccAhb1enr = 0x4002'3830;  // RCC_AHB1ENR (7.3.10)
inline constexpr std::uintptr_t kGpioA = 0x4002'0000;       // RM0090 2.3, Table 1; GPIOB..I follow every 0x400
// GPIO registers (8.4.1-8.4.10)
inline constexpr std::uintptr_t kModer = 0x00;    // 2 bits per pin: 10 = alternate function
inline constexpr std::uintptr_t kOtyper = 0x04;   // 1 bit per pin: 0 = push-pull
inline constexpr std::uintptr_t kOspeedr = 0x08;  // 2 bits per pin: 01 = medium (25 MHz at 3.3 V), ample for a UART
inline constexpr std::uintptr_t kPupdr = 0x0C;    // 2 bits per pin: 01 = pull-up (an idle UART line is high)
inline constexpr std::uintptr_t kAfrl = 0x20;     // 4 bits per pin, pins 0-7
inline constexpr std::uintptr_t kAfrh = 0x24;     // 4 bits per pin, pins 8-15
}  // namespace pin_registers

/// USART1 on PA9 (TX) and PA10 (RX), USART2 on PA2 (TX) and PA3 (RX): AF7 (DS8626 Table 9).
inline constexpr UsartPins kUsart1PinsPA9PA10{pin_registers::kGpioA, 1U << 0, 9, 10, 7};
inline constexpr UsartPins kUsart2PinsPA2PA3{pin_registers::kGpioA, 1U << 0, 2, 3, 7};

/// Clocks the GPIO port and puts both pins in alternate-function mode, push-pull, medium speed, pulled up, on the
/// USART's alternate function. The other pins of the port keep their settings (read-modify-write).
template <RegisterBus Bus>
void route_usart_pins(Bus& bus, const UsartPins& pins) {
  using namespace pin_registers;
  bus.write(kRccAhb1enr, bus.read(kRccAhb1enr) | pins.rcc_ahb1enr_bit);
  (void)bus.read(kRccAhb1enr);  // the enable takes effect before the port is accessed (ES0182 2.1.13)
  const auto field = [&](std::uintptr_t offset, std::uint32_t pin, std::uint32_t width, std::uint32_t value) {
    const std::uint32_t shift = pin * width;
    const std::uint32_t mask = ((1U << width) - 1U) << shift;
    bus.write(pins.gpio_base + offset, (bus.read(pins.gpio_base + offset) & ~mask) | (value << shift));
  };
  for (const std::uint32_t pin : {pins.tx_pin, pins.rx_pin}) {
    // The alternate function first, then the mode: the pin never drives the line as another function.
    field(pin < 8 ? kAfrl : kAfrh, pin % 8, 4, pins.alternate_function);
    field(kOtyper, pin, 1, 0U);
    field(kOspeedr, pin, 2, 1U);
    field(kPupdr, pin, 2, 1U);
    field(kModer, pin, 2, 2U);
  }
}

}  // namespace lashid::hal::stm32f4
