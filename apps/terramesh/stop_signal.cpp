#include "stop_signal.h"

#include <csignal>

namespace terramesh::cli {
namespace {

// The one flag the handler may touch (a handler can reach nothing else safely).
volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void onStopSignal(int signal) {
  if (g_stop_signal != 0) {
    // Second request: stop now.
    std::signal(signal, SIG_DFL);
    std::raise(signal);
    return;
  }
  g_stop_signal = signal;
}

struct sigaction g_previous_int;
struct sigaction g_previous_term;

}  // namespace

StopSignalScope::StopSignalScope() {
  g_stop_signal = 0;
  struct sigaction action {};
  action.sa_handler = onStopSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // reads and writes in progress carry on
  sigaction(SIGINT, &action, &g_previous_int);
  sigaction(SIGTERM, &action, &g_previous_term);
}

StopSignalScope::~StopSignalScope() {
  sigaction(SIGINT, &g_previous_int, nullptr);
  sigaction(SIGTERM, &g_previous_term, nullptr);
}

int StopSignalScope::requested() { return g_stop_signal; }

}  // namespace terramesh::cli
