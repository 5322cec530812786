// The processes one run is spread over (`mpirun -np N vktg ...`, docs/mpi.md): each renders its
// share of the targets, views or scan points, and what they computed is combined so that the
// result does not depend on N. The library knows only this interface; the command line implements
// it over MPI (src/cli/mpi_world.h), so neither libvktg nor its headers depend on MPI. A run of one
// process passes no Collective at all and takes the code path it always took.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "render/renderer.h"
#include "vktg/image_io.h"

namespace vktg {

class Collective {
 public:
  virtual ~Collective() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  bool root() const { return rank() == 0; }

  // Every call below is collective: each process makes the same calls in the same order.
  // values := the sum over processes, modulo 2^64: the integer accumulators' sum is exact and does
  // not depend on the order the processes add in (the device's atomic adds wrap the same way).
  virtual void sumWrapping(std::span<uint64_t> values) = 0;
  // values := the largest over processes, element by element.
  virtual void max(std::span<double> values) = 0;
  // bytes := rank 0's bytes.
  virtual void broadcast(std::vector<uint8_t>& bytes) = 0;
  // Every process's bytes, in rank order, on every process.
  virtual std::vector<std::vector<uint8_t>> allGather(const std::vector<uint8_t>& bytes) = 0;
  // Every process's bytes, in rank order, on rank 0; nothing elsewhere.
  virtual std::vector<std::vector<uint8_t>> gather(const std::vector<uint8_t>& bytes) = 0;

  // Whether any process passes true.
  bool any(bool flag);
  // The processes compare how a step went: `error` is this one's failure ("" when it succeeded).
  // Where any failed, every process throws the same vktg::Error (the lowest failing rank's
  // message, its rank named where there are several), and failureAgreed() turns true: every
  // process then ends on its own, none waiting for another.
  void agree(const std::string& error);
  bool failureAgreed() const { return m_failureAgreed; }
  // The interruption signal any process received (the largest number where several did), 0 when
  // none did; a run that stops for it on every process counts as an agreed failure.
  int agreeOnInterrupt(int signal);

 private:
  bool m_failureAgreed = false;
};

// The items [begin, end) of `count` that a process renders: consecutive blocks in rank order, the
// first count % size processes one item more, so that rank 0 has one whenever there is any.
struct Share {
  size_t begin = 0, end = 0;
  size_t size() const { return end - begin; }
  bool empty() const { return begin == end; }
};
Share shareOf(size_t count, int rank, int size);
// All of them for a run of one process (`collective` null).
Share shareOf(size_t count, const Collective* collective);

// Every process's doubles, one after another in rank order, on every process.
std::vector<double> allGatherDoubles(Collective& collective, const std::vector<double>& values);
// rank 0's value on every process.
double broadcastDouble(Collective& collective, double value);
// Every process's images, one after another in rank order: on every process, or on rank 0 alone
// (gatherImages: empty elsewhere).
std::vector<ImageSet> allGatherImages(Collective& collective, const std::vector<ImageSet>& images);
std::vector<ImageSet> gatherImages(Collective& collective, const std::vector<ImageSet>& images);
// The image of a render of several views (Renderer::render of RenderViews) from each process's
// render of its share of them (consecutive shares in rank order): on rank 0, each layer the
// processes' rows one below the other, as one render of all the views stacks them; an empty image
// elsewhere. A process without views passes an image without layers.
ImageSet gatherStackedViews(Collective& collective, const ImageSet& mine);
// The same for several images at once, each stacked with the same image of the other processes.
std::vector<ImageSet> gatherStackedViews(Collective& collective, const std::vector<ImageSet>& mine);
// The counters of every process's renders summed (paths, rays, non-finite samples...), so that
// every process reports, and decides by, the whole run's.
void sumStats(Collective& collective, RenderStats& stats);

}  // namespace vktg
