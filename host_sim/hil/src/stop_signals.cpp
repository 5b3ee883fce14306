#include "stop_signals.hpp"

#include <signal.h>

#include <array>
#include <csignal>
#include <string>

#include <fmt/format.h>

#include "lashid/hil/hil.hpp"

namespace lashid::sim::detail {

namespace {

volatile std::sig_atomic_t g_stop_signal = 0;
constexpr std::array<int, 3> kStopSignals = {SIGINT, SIGTERM, SIGHUP};
std::array<struct sigaction, kStopSignals.size()> g_previous{};

extern "C" void note_stop_signal(int number) { g_stop_signal = number; }

}  // namespace

StopSignals::StopSignals() {
  g_stop_signal = 0;
  struct sigaction action {};
  action.sa_handler = note_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;
  for (std::size_t i = 0; i < kStopSignals.size(); ++i) ::sigaction(kStopSignals[i], &action, &g_previous[i]);
}

StopSignals::~StopSignals() {
  for (std::size_t i = 0; i < kStopSignals.size(); ++i) ::sigaction(kStopSignals[i], &g_previous[i], nullptr);
}

void throw_if_stopped() {
  const int number = g_stop_signal;
  if (number == 0) return;
  const char* name = number == SIGINT ? "SIGINT" : number == SIGTERM ? "SIGTERM" : number == SIGHUP ? "SIGHUP" : "a signal";
  throw HilInterrupted(fmt::format("hil: stopped by {} (signal {})", name, number), number);
}

}  // namespace lashid::sim::detail
