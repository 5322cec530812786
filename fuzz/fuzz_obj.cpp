// Fuzz target: the OBJ mesh reader (parseObjMesh, src/scene/obj_mesh.cpp: tinyobjloader and the
// line pass around it) on text in memory. Every input must end in a well-formed mesh or one
// vktg::Error.
// vktg-fuzz-links: vktg_scene
// vktg-fuzz-seeds: tests/data/meshes/*.obj tests/data/fuzz/*.obj
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "scene/mesh_files.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  vktg::fuzz::expectOnlyVktgErrors([&] { vktg::fuzz::expectWellFormed(vktg::parseObjMesh(text, "input.obj")); });
  return 0;
}
