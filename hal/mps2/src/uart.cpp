// CMSDK APB UART, polled.
#include "lashid/hal/mps2.hpp"
#include "registers.hpp"

namespace lashid::hal::mps2 {

namespace {
constexpr std::uint32_t kTxPollLimit = 1'000'000;  // ~40 baud periods at 115200 even at 1 poll per 10 ns
}  // namespace

void Mps2Uart::init(std::uint32_t baud) const {
  using namespace detail;
  reg(base_ + kUartCtrl) = 0;
  // BAUDDIV = PCLK / baud, at least 16 (QEMU ignores smaller divisors; the hardware requires >= 16).
  std::uint32_t div = baud == 0 ? 16U : kSystemClockHz / baud;
  if (div < 16U) div = 16U;
  reg(base_ + kUartBaudDiv) = div;
  reg(base_ + kUartState) = kUartTxOverrun | kUartRxOverrun;      // clear sticky errors (W1C)
  reg(base_ + kUartIntStatus) = 0xFU;                              // and any interrupt status
  reg(base_ + kUartCtrl) = kUartTxEnable | kUartRxEnable;
}

Status Mps2Uart::write(const std::uint8_t* data, std::size_t size) const {
  using namespace detail;
  for (std::size_t i = 0; i < size; ++i) {
    std::uint32_t polls = 0;
    while ((reg(base_ + kUartState) & kUartTxFull) != 0U) {
      if (++polls == kTxPollLimit) return Status::kTimeout;
    }
    reg(base_ + kUartData) = data[i];
  }
  return Status::kOk;
}

Status Mps2Uart::write(const char* text) const {
  std::size_t n = 0;
  while (text[n] != '\0') ++n;
  return write(reinterpret_cast<const std::uint8_t*>(text), n);
}

Status Mps2Uart::read(std::uint8_t& byte) const {
  using namespace detail;
  const std::uint32_t state = reg(base_ + kUartState);
  if ((state & kUartRxOverrun) != 0U) {
    reg(base_ + kUartState) = kUartRxOverrun;
    return Status::kLinkError;
  }
  if ((state & kUartRxFull) == 0U) return Status::kWouldBlock;
  byte = static_cast<std::uint8_t>(reg(base_ + kUartData) & 0xFFU);
  return Status::kOk;
}

bool Mps2Uart::rx_pending() const {
  using namespace detail;
  return (reg(base_ + kUartState) & (kUartRxFull | kUartRxOverrun)) != 0U;
}

void Mps2Uart::arm_rx_wake() const {
  using namespace detail;
  reg(base_ + kUartCtrl) = reg(base_ + kUartCtrl) | kUartRxIntEnable;
}

void Mps2Uart::disarm_rx_wake() const {
  using namespace detail;
  reg(base_ + kUartCtrl) = reg(base_ + kUartCtrl) & ~kUartRxIntEnable;
  reg(base_ + kUartIntStatus) = kUartIntRx;
}

Mps2Uart::Errors Mps2Uart::errors() const {
  using namespace detail;
  const std::uint32_t state = reg(base_ + kUartState);
  return Errors{(state & kUartRxOverrun) != 0U, (state & kUartTxOverrun) != 0U};
}

void Mps2Uart::clear_errors() const {
  using namespace detail;
  reg(base_ + kUartState) = kUartTxOverrun | kUartRxOverrun;
}

}  // namespace lashid::hal::mps2
