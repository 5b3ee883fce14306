// STM32F4 USART, polled (RM0090 30). QEMU 7.2's model (hw/char/stm32f2xx_usart.c) implements SR, DR, BRR, CR1..CR3
// and GTPR: TXE and TC are always set (its writes are synchronous), RXNE is set by a received byte and cleared by a DR
// read, and received bytes are dropped while UE or RE is clear. It never sets ORE (it stops accepting input instead).
#include "lashid/hal/stm32f4.hpp"
#include "registers.hpp"

namespace lashid::hal::stm32f4 {

namespace {
constexpr std::uint32_t kTxPollLimit = 1'000'000;  // ~80 character times at 115200 baud even at 1 poll per 10 ns
}  // namespace

void Usart::init(std::uint32_t baud) const {
  using namespace detail;
  MmioBus bus;
  route_usart_pins(bus, port_.pins);
  // The peripheral's clock first (RM0090 7.3.13/7.3.14); read back so that the enable has taken effect before the
  // first register access (two AHB cycles are needed, STM32F40x errata ES0182 2.1.13).
  reg(port_.rcc_enable_register) = reg(port_.rcc_enable_register) | port_.rcc_enable_bit;
  const std::uint32_t enabled = reg(port_.rcc_enable_register);
  (void)enabled;
  reg(port_.base + kUsartCr1) = 0;  // UE = 0 while configuring
  reg(port_.base + kUsartCr2) = 0;  // 1 stop bit
  reg(port_.base + kUsartCr3) = 0;  // no flow control, no DMA
  // 16x oversampling: USARTDIV = PCLK / (16 baud), and BRR = mantissa << 4 | fraction = round(16 USARTDIV) =
  // round(PCLK / baud) (RM0090 30.3.4, Table 136: 115200 baud at 84 MHz -> 0x2D9, 0.02 % error).
  const std::uint32_t b = baud == 0U ? kDefaultBaud : baud;
  reg(port_.base + kUsartBrr) = (port_.pclk_hz + b / 2U) / b;
  reg(port_.base + kUsartCr1) = kCr1Ue | kCr1Te | kCr1Re;
}

Status Usart::write(const std::uint8_t* data, std::size_t size) const {
  using namespace detail;
  for (std::size_t i = 0; i < size; ++i) {
    std::uint32_t polls = 0;
    while ((reg(port_.base + kUsartSr) & kSrTxe) == 0U) {
      if (++polls == kTxPollLimit) return Status::kTimeout;
    }
    reg(port_.base + kUsartDr) = data[i];
  }
  return Status::kOk;
}

Status Usart::write(const char* text) const {
  std::size_t n = 0;
  while (text[n] != '\0') ++n;
  return write(reinterpret_cast<const std::uint8_t*>(text), n);
}

Status Usart::read(std::uint8_t& byte) const {
  using namespace detail;
  const std::uint32_t sr = reg(port_.base + kUsartSr);
  if ((sr & kSrRxErrors) != 0U) {
    // RM0090 30.6.1: ORE, NF, FE and PE are cleared by reading SR and then DR; the byte in DR goes with them (bytes
    // were lost already; the link protocol's CRC and retries recover).
    const std::uint32_t dropped = reg(port_.base + kUsartDr);
    (void)dropped;
    return Status::kLinkError;
  }
  if ((sr & kSrRxne) == 0U) return Status::kWouldBlock;
  byte = static_cast<std::uint8_t>(reg(port_.base + kUsartDr) & 0xFFU);
  return Status::kOk;
}

bool Usart::rx_pending() const {
  using namespace detail;
  return (reg(port_.base + kUsartSr) & (kSrRxne | kSrRxErrors)) != 0U;
}

void Usart::arm_rx_wake() const {
  using namespace detail;
  reg(port_.base + kUsartCr1) = reg(port_.base + kUsartCr1) | kCr1Rxneie;
  cortex_m::clear_pending_irq(port_.irq);
  cortex_m::enable_irq(port_.irq);
}

void Usart::disarm_rx_wake() const { cortex_m::disable_irq(port_.irq); }

}  // namespace lashid::hal::stm32f4
