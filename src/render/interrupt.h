// Cooperative interruption. SIGINT and SIGTERM only set a flag; long-running loops poll it at safe
// points (between batches, between optimisation iterations), so a run stops where nothing is half
// written: outputs are never written partially (they are written atomically after the work), and
// `vktg optimize` leaves a valid checkpoint.
#pragma once
#include "vktg/error.h"

namespace vktg {

// throwIfInterrupted throws vktg::Interrupted (vktg/error.h).
// Routes SIGINT and SIGTERM to the flag (idempotent). A second signal while the first is pending
// takes the default action (the process ends), so a stuck run can still be stopped.
void installInterruptHandlers();
// The signal that asked the run to stop, or 0.
int interruptSignal();
bool interruptRequested();
// Throws Interrupted if a signal arrived.
void throwIfInterrupted();
// Forgets a pending request (tests).
void clearInterrupt();
// Asks the run to stop as if `signal` had arrived (tests, fault injection).
void requestInterrupt(int signal);

}  // namespace vktg
