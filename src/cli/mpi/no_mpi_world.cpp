// The world of a vktg built without MPI: always a process on its own. Started as one of several
// (mpirun found at run time but not at configure time), it would repeat the whole run in every
// process, all writing the same files: it refuses instead.
#include <cstdlib>
#include <string>

#include "cli/mpi_world.h"
#include "vktg/error.h"

namespace vktg::cli {

Collective* joinWorld() {
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    const char* size = std::getenv(variable);
    if (size && std::string(size) != "1")
      throw Error(std::string("started as one of ") + size + " MPI processes (" + variable +
                  "), but this vktg was built without MPI: install libopenmpi-dev and build again (docs/mpi.md)");
  }
  return nullptr;
}

Collective* world() { return nullptr; }
int localRank() { return 0; }
void leaveWorld() {}
void abortWorld(int status) { std::exit(status); }

}  // namespace vktg::cli
