// Triangle meshes from the files the field's scenes refer to: Wavefront OBJ and Stanford PLY
// (ASCII, binary little and big endian). Positions only, in the file's own frame; polygons are
// split into fans. Every error is a vktg::Error naming the file, the line or element, and the
// problem (docs/scene-format.md, "Mesh files").
#pragma once
#include <filesystem>
#include <string>

#include "scene/primitives.h"

namespace vktg {

TriangleMesh loadObjMesh(const std::filesystem::path& path);
TriangleMesh loadPlyMesh(const std::filesystem::path& path);
// The same readers on bytes in memory (`file` names the source in errors): the fuzz targets' entry.
TriangleMesh parseObjMesh(const std::string& bytes, const std::string& file);
TriangleMesh parsePlyMesh(const std::string& bytes, const std::string& file);

}  // namespace vktg
