// The world over MPI (built where CMake found MPI; no_mpi_world.cpp elsewhere).
// The C interface only: mpi.h in C++ otherwise declares the long-removed C++ bindings, which the C
// library does not define.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <ctime>
#include <cstdlib>
#include <memory>
#include <optional>

#include "cli/mpi_world.h"
#include "render/interrupt.h"
#include "vktg/error.h"

namespace vktg::cli {
namespace {

// MPI counts are ints: larger messages go in pieces.
constexpr size_t kPiece = size_t(1) << 30;

// Waits for an exchange without spinning: MPI's blocking calls poll at full speed, and a process
// that waits for its peers would take the cores they render on (processes sharing lavapipe, or
// more processes than cores). A tenth of a millisecond between polls costs nothing next to a render.
// Interrupted while it waits, a process gives its peers a while to reach the exchange (they were
// most likely interrupted too, and the run stops where all agree); a peer still missing then will
// not come (it stopped mid-render), and this process stops too (main.cpp then ends them all).
void finish(MPI_Request& request) {
  constexpr auto kGrace = std::chrono::seconds(2);
  std::optional<std::chrono::steady_clock::time_point> interruptedAt;
  for (int done = 0;;) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done) return;
    if (interruptRequested()) {
      const auto now = std::chrono::steady_clock::now();
      if (!interruptedAt) interruptedAt = now;
      if (now - *interruptedAt > kGrace) throwIfInterrupted();
    }
    const timespec pause = {0, 100000};
    nanosleep(&pause, nullptr);
  }
}

class MpiWorld final : public Collective {
 public:
  MpiWorld() {
    MPI_Init(nullptr, nullptr);
    MPI_Comm_rank(MPI_COMM_WORLD, &m_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &m_size);
    MPI_Comm local;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &local);
    MPI_Comm_rank(local, &m_localRank);
    MPI_Comm_free(&local);
  }
  int rank() const override { return m_rank; }
  int size() const override { return m_size; }
  int localRank() const { return m_localRank; }

  void sumWrapping(std::span<uint64_t> values) override {
    for (size_t at = 0; at < values.size(); at += kPiece)
      reduce(values.data() + at, int(std::min(kPiece, values.size() - at)), MPI_UINT64_T, MPI_SUM);
  }
  void max(std::span<double> values) override {
    for (size_t at = 0; at < values.size(); at += kPiece)
      reduce(values.data() + at, int(std::min(kPiece, values.size() - at)), MPI_DOUBLE, MPI_MAX);
  }
  void broadcast(std::vector<uint8_t>& bytes) override { broadcastFrom(0, bytes); }
  std::vector<std::vector<uint8_t>> allGather(const std::vector<uint8_t>& bytes) override {
    std::vector<std::vector<uint8_t>> out(static_cast<size_t>(m_size));
    for (int r = 0; r < m_size; ++r) {
      if (r == m_rank) out[size_t(r)] = bytes;
      broadcastFrom(r, out[size_t(r)]);
    }
    return out;
  }
  std::vector<std::vector<uint8_t>> gather(const std::vector<uint8_t>& bytes) override {
    if (m_rank != 0) {
      uint64_t size = bytes.size();
      send(&size, 1, MPI_UINT64_T);
      for (size_t at = 0; at < bytes.size(); at += kPiece) send(bytes.data() + at, int(std::min(kPiece, bytes.size() - at)), MPI_BYTE);
      return {};
    }
    std::vector<std::vector<uint8_t>> out(static_cast<size_t>(m_size));
    out[0] = bytes;
    for (int r = 1; r < m_size; ++r) {
      uint64_t size = 0;
      receive(&size, 1, MPI_UINT64_T, r);
      out[size_t(r)].resize(size);
      for (size_t at = 0; at < size; at += kPiece)
        receive(out[size_t(r)].data() + at, int(std::min(kPiece, size_t(size) - at)), MPI_BYTE, r);
    }
    return out;
  }

 private:
  void broadcastFrom(int root, std::vector<uint8_t>& bytes) {
    uint64_t size = bytes.size();
    bcast(&size, 1, MPI_UINT64_T, root);
    bytes.resize(size);
    for (size_t at = 0; at < size; at += kPiece) bcast(bytes.data() + at, int(std::min(kPiece, size_t(size) - at)), MPI_BYTE, root);
  }
  static void reduce(void* data, int count, MPI_Datatype type, MPI_Op op) {
    MPI_Request request;
    MPI_Iallreduce(MPI_IN_PLACE, data, count, type, op, MPI_COMM_WORLD, &request);
    finish(request);
  }
  static void bcast(void* data, int count, MPI_Datatype type, int root) {
    MPI_Request request;
    MPI_Ibcast(data, count, type, root, MPI_COMM_WORLD, &request);
    finish(request);
  }
  static void send(const void* data, int count, MPI_Datatype type) {
    MPI_Request request;
    MPI_Isend(data, count, type, 0, 0, MPI_COMM_WORLD, &request);
    finish(request);
  }
  static void receive(void* data, int count, MPI_Datatype type, int from) {
    MPI_Request request;
    MPI_Irecv(data, count, type, from, 0, MPI_COMM_WORLD, &request);
    finish(request);
  }

  int m_rank = 0, m_size = 1, m_localRank = 0;
};

std::unique_ptr<MpiWorld> g_world;

// What the launchers that start MPI programs put in each process's environment (OpenMPI's mpirun,
// PMIx and PMI launchers such as Slurm's srun and MPICH's hydra).
bool startedByLauncher() {
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"})
    if (std::getenv(variable)) return true;
  return false;
}

}  // namespace

Collective* joinWorld() {
  if (!g_world && startedByLauncher()) g_world = std::make_unique<MpiWorld>();
  return g_world.get();
}

Collective* world() { return g_world.get(); }
int localRank() { return g_world ? g_world->localRank() : 0; }

void leaveWorld() {
  if (!g_world) return;
  g_world.reset();
  MPI_Finalize();
}

void abortWorld(int status) {
  if (g_world) MPI_Abort(MPI_COMM_WORLD, status);
  std::exit(status);
}

}  // namespace vktg::cli
