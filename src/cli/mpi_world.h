// The processes of `mpirun -np N vktg ...` (docs/mpi.md). A process started by an MPI launcher
// joins the world of its peers; one started any other way stays alone and runs exactly as it
// always did. Built without MPI (no libopenmpi-dev at configure time), vktg refuses to run as one
// of several processes rather than repeat the whole run in each.
#pragma once
#include "grad/collective.h"

namespace vktg::cli {

// Joins the world when an MPI launcher started this process (the launcher's environment says so);
// once, before anything else. Returns world().
Collective* joinWorld();
// The world this process joined; null for a process on its own.
Collective* world();
// Which of the processes on this machine this one is (0 for a process on its own): the one that
// picks the local rank-th GPU.
int localRank();
// This process's part ends normally: every process got here, or all agreed on a failure.
void leaveWorld();
// This process failed where its peers may be waiting for it: ends every process of the run at
// once with `status`.
[[noreturn]] void abortWorld(int status);

}  // namespace vktg::cli
