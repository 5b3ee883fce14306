#include "lashid/io/stop_signals.hpp"

#include <signal.h>

#include <array>
#include <csignal>

#include <fmt/format.h>

namespace lashid::sim {

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

int pending_stop_signal() { return g_stop_signal; }

std::string stopped_message(std::string_view command, int signal) {
  const char* name = signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : signal == SIGHUP ? "SIGHUP" : "a signal";
  return fmt::format("{}: stopped by {} (signal {})", command, name, signal);
}

void throw_if_stopped(std::string_view command) {
  const int number = g_stop_signal;
  if (number != 0) throw Interrupted(stopped_message(command, number), number);
}

}  // namespace lashid::sim
