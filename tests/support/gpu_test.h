// GPU unit tests: run a tiny kernel (tests/shaders/NAME.comp) that calls production shader
// functions, and compare its output with a CPU reference element by element.
//
// A test kernel includes "lib/common.glsl", "lib/bindings.glsl" and "test_io.glsl" (which
// declares `testIn`/`testOut` as uint arrays at kBindingTestIn/kBindingTestOut and the push
// constant `invocationCount`), reads its inputs with uintBitsToFloat, writes outputs likewise.
// Validation layers are on; any validation message fails the running test.
#pragma once
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "vktg/gpu/shared.h"
#include "vktg/scene.h"

namespace vktg::test {

// Raw form: input/output as 32-bit words. `scene` (optional) is uploaded and bound like in a
// render (triangles, BVH, lights, frame uniforms), so kernels can trace rays. `ellipsoidSelection`
// specialises kSpecEllipsoidSelection (kEllipsoidDescend / kEllipsoidEnumerate). `edges`
// (optional) is bound as the edge list (kBindingEdges, its count in frame.edgeInfo.x).
std::vector<uint32_t> runKernelWords(const std::string& kernel, const std::vector<uint32_t>& input,
                                     size_t outputWords, uint32_t invocations, const Scene* scene = nullptr,
                                     uint32_t ellipsoidSelection = gpu::kEllipsoidDescend,
                                     const std::vector<gpu::GpuEdge>* edges = nullptr);

// Typed convenience: In and Out are trivially copyable structs of 32-bit fields.
template <class Out, class In>
std::vector<Out> runKernel(const std::string& kernel, const std::vector<In>& input, size_t outputCount,
                           uint32_t invocations, const Scene* scene = nullptr,
                           uint32_t ellipsoidSelection = gpu::kEllipsoidDescend) {
  static_assert(sizeof(In) % 4 == 0 && sizeof(Out) % 4 == 0);
  std::vector<uint32_t> words(input.size() * sizeof(In) / 4);
  if (!input.empty()) std::memcpy(words.data(), input.data(), input.size() * sizeof(In));
  std::vector<uint32_t> raw = runKernelWords(kernel, words, outputCount * sizeof(Out) / 4, invocations, scene, ellipsoidSelection);
  std::vector<Out> out(outputCount);
  std::memcpy(out.data(), raw.data(), outputCount * sizeof(Out));
  return out;
}

}  // namespace vktg::test
