#include "render/interrupt.h"

#include <atomic>
#include <csignal>
#include <cstring>
#include <string>

namespace vktg {
namespace {

std::atomic<int> g_signal{0};

extern "C" void onInterruptSignal(int signal) {
  int expected = 0;
  // A second signal while the first is still being honoured: the default action, at once.
  if (!g_signal.compare_exchange_strong(expected, signal)) {
    std::signal(signal, SIG_DFL);
    std::raise(signal);
  }
}

}  // namespace

Interrupted::Interrupted(int signal)
    : Error(std::string("interrupted by ") + (signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "a signal")),
      m_signal(signal) {}

void installInterruptHandlers() {
  struct sigaction action;
  std::memset(&action, 0, sizeof action);
  action.sa_handler = onInterruptSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

int interruptSignal() { return g_signal.load(); }
bool interruptRequested() { return g_signal.load() != 0; }

void throwIfInterrupted() {
  if (int s = g_signal.load()) throw Interrupted(s);
}

void clearInterrupt() { g_signal.store(0); }
void requestInterrupt(int signal) { g_signal.store(signal); }

}  // namespace vktg
