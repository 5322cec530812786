// What every fuzz target shares: the rule that a bad input may only end in vktg's own errors, and
// the post-parse step every command runs on a scene.
#pragma once
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>

#include "scene/primitives.h"
#include "vktg/error.h"
#include "vktg/prepared_scene.h"
#include "vktg/scene.h"

namespace vktg::fuzz {

// Runs `body`; a vktg::Error is the expected way to reject an input, any other exception is a
// finding (abort, so libFuzzer keeps the input).
template <class Body>
void expectOnlyVktgErrors(const Body& body) {
  try {
    body();
  } catch (const vktg::Error&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz: unexpected exception: %s\n", e.what());
    std::abort();
  } catch (...) {
    std::fprintf(stderr, "fuzz: unexpected non-standard exception\n");
    std::abort();
  }
}

// Large but valid scenes (a 4096^2 heightfield) are slow to flatten, not wrong; skip them so the
// fuzzer's time goes to the parsers. The bound is far above every test and example scene.
inline void prepareIfSmall(const Scene& scene) {
  constexpr size_t kMaxTriangles = size_t(1) << 16;
  if (scene.triangleCount() <= kMaxTriangles) prepareScene(scene);
}

// What a mesh reader promises of every mesh it returns: at least one triangle, every index in
// range, every coordinate finite. A broken promise is a finding (abort, so libFuzzer keeps it).
inline void expectWellFormed(const TriangleMesh& mesh) {
  bool ok = !mesh.triangles.empty() && allFinite(mesh.positions);
  for (const glm::uvec3& t : mesh.triangles)
    ok = ok && t.x < mesh.positions.size() && t.y < mesh.positions.size() && t.z < mesh.positions.size();
  if (!ok) {
    std::fprintf(stderr, "fuzz: the reader returned a malformed mesh\n");
    std::abort();
  }
}

// A directory only this process writes to, removed when the process exits.
class TemporaryDirectory {
 public:
  TemporaryDirectory() {
    // mkdtemp's template: it replaces the trailing six X with a unique suffix.
    std::string pattern = (std::filesystem::temp_directory_path() / "vktg-fuzz-XXXXXX").string();
    if (!mkdtemp(pattern.data())) std::abort();
    m_path = pattern;
  }
  ~TemporaryDirectory() {
    std::error_code ignored;
    std::filesystem::remove_all(m_path, ignored);
  }
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;
  const std::filesystem::path& path() const { return m_path; }

 private:
  std::filesystem::path m_path;
};

}  // namespace vktg::fuzz
