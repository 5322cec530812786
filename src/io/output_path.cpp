// Up-front validation of an output path, so a command fails before doing any work when its
// result could not be written or would overwrite one of its own inputs.
#include <unistd.h>

#include <cerrno>

#include "io/io_internal.h"
#include "vktg/error.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;

// Same file if the file system says so (hard links, symlinks, different spellings); when either
// does not exist yet, compare canonical spellings (symlinks in existing parents resolved).
bool sameFile(const fs::path& a, const fs::path& b) {
  std::error_code error;
  if (fs::exists(a, error) && fs::exists(b, error)) {
    const bool same = fs::equivalent(a, b, error);
    if (!error) return same;
  }
  const fs::path canonicalA = fs::weakly_canonical(a, error);
  if (error) return fs::absolute(a).lexically_normal() == fs::absolute(b).lexically_normal();
  const fs::path canonicalB = fs::weakly_canonical(b, error);
  if (error) return fs::absolute(a).lexically_normal() == fs::absolute(b).lexically_normal();
  return canonicalA == canonicalB;
}

}  // namespace

void checkOutputPath(const fs::path& output, const std::vector<fs::path>& inputs) {
  const std::string name = output.string();
  if (output.empty() || !output.has_filename()) fail(name, "", "the output path does not name a file");
  for (const fs::path& input : inputs) {
    if (sameFile(output, input)) fail(name, "", "refusing to overwrite input file '" + input.string() + "'");
  }
  const fs::path directory = output.parent_path().empty() ? fs::path(".") : output.parent_path();
  std::error_code error;
  if (!fs::exists(directory, error)) fail(name, "", "cannot write: directory '" + directory.string() + "' does not exist");
  if (!fs::is_directory(directory, error)) fail(name, "", "cannot write: '" + directory.string() + "' is not a directory");
  if (fs::is_directory(output, error)) fail(name, "", "cannot write: it is a directory");
  // Creating the temporary file and renaming it needs write and search permission on the directory.
  if (::access(directory.c_str(), W_OK | X_OK) != 0) {
    fail(name, "", "cannot write: directory '" + directory.string() + "' is not writable (" + io::describeErrno(errno) + ")");
  }
}

}  // namespace vktg
