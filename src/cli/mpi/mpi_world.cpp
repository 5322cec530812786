// The world over MPI (built where CMake found MPI; no_mpi_world.cpp elsewhere).
// The C interface only: mpi.h in C++ otherwise declares the long-removed C++ bindings, which the C
// library does not define.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <algorithm>
#include <climits>
#include <cstdlib>
#include <memory>

#include "cli/mpi_world.h"
#include "vktg/error.h"

namespace vktg::cli {
namespace {

// MPI counts are ints: larger messages go in pieces.
constexpr size_t kPiece = size_t(1) << 30;

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
      MPI_Allreduce(MPI_IN_PLACE, values.data() + at, int(std::min(kPiece, values.size() - at)), MPI_UINT64_T, MPI_SUM,
                    MPI_COMM_WORLD);
  }
  void max(std::span<double> values) override {
    for (size_t at = 0; at < values.size(); at += kPiece)
      MPI_Allreduce(MPI_IN_PLACE, values.data() + at, int(std::min(kPiece, values.size() - at)), MPI_DOUBLE, MPI_MAX,
                    MPI_COMM_WORLD);
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
      MPI_Send(&size, 1, MPI_UINT64_T, 0, 0, MPI_COMM_WORLD);
      for (size_t at = 0; at < bytes.size(); at += kPiece)
        MPI_Send(bytes.data() + at, int(std::min(kPiece, bytes.size() - at)), MPI_BYTE, 0, 0, MPI_COMM_WORLD);
      return {};
    }
    std::vector<std::vector<uint8_t>> out(static_cast<size_t>(m_size));
    out[0] = bytes;
    for (int r = 1; r < m_size; ++r) {
      uint64_t size = 0;
      MPI_Recv(&size, 1, MPI_UINT64_T, r, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      out[size_t(r)].resize(size);
      for (size_t at = 0; at < size; at += kPiece)
        MPI_Recv(out[size_t(r)].data() + at, int(std::min(kPiece, size_t(size) - at)), MPI_BYTE, r, 0, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE);
    }
    return out;
  }

 private:
  void broadcastFrom(int root, std::vector<uint8_t>& bytes) {
    uint64_t size = bytes.size();
    MPI_Bcast(&size, 1, MPI_UINT64_T, root, MPI_COMM_WORLD);
    bytes.resize(size);
    for (size_t at = 0; at < size; at += kPiece)
      MPI_Bcast(bytes.data() + at, int(std::min(kPiece, size_t(size) - at)), MPI_BYTE, root, MPI_COMM_WORLD);
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
