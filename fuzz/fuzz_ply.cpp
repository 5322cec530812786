// Fuzz target: the PLY mesh reader (parsePlyMesh, src/scene/ply_mesh.cpp), ASCII and binary, on
// bytes in memory. Every input must end in a well-formed mesh or one vktg::Error.
// vktg-fuzz-links: vktg_scene
// vktg-fuzz-seeds: tests/data/meshes/*.ply tests/data/fuzz/*.ply
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "scene/mesh_files.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  vktg::fuzz::expectOnlyVktgErrors([&] { vktg::fuzz::expectWellFormed(vktg::parsePlyMesh(bytes, "input.ply")); });
  return 0;
}
