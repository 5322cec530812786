// End-to-end tests of the `vktg` executable (the path in VKTG_BINARY): run it as a child process
// with arguments, environment and working directory, capture exit status, stdout and stderr, and
// kill it after a timeout so that a hang fails the test instead of stalling the suite.
#pragma once
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace vktg::test {

struct CliResult {
  bool exited = false;    // ended through exit(); false after a signal or a timeout
  int exitCode = -1;      // valid when exited
  int signal = 0;         // the terminating signal, 0 when exited
  bool timedOut = false;  // killed by the runner after the timeout
  double seconds = 0;     // wall-clock time
  std::string out, err;

  // "exit 0", "signal 11 (Segmentation fault)", "timed out after ..." plus both streams, for
  // failure messages.
  std::string describe() const;
};

struct CliOptions {
  std::map<std::string, std::string> env;  // set (over the inherited environment) in the child
  std::filesystem::path cwd;               // working directory; empty: inherit
  double timeoutSeconds = 300;
  // Non-empty: once the child's stderr contains this text, the runner sends it `signal` (once), as
  // a user's Ctrl-C would.
  std::string signalWhen;
  int signal = 2;  // SIGINT
  // The child runs without root's permission override (support/file_permissions.h), so
  // permission-denied cases hold as root too; check canDropFileOverrideForExec() first.
  bool enforcePermissions = false;
};

// Runs VKTG_BINARY with `args`. The child always runs with VKTG_VALIDATION=1 (so a validation
// message makes vktg exit 3) unless `options.env` says otherwise; the rest of the environment,
// including ctest's VK_DRIVER_FILES, is inherited.
CliResult runVktg(const std::vector<std::string>& args, const CliOptions& options = {});
// The same for another program (argv[0], a path) that runs vktg, as mpirun does.
CliResult runProgram(const std::vector<std::string>& argv, const CliOptions& options = {});

// Lines of `text` that start with `prefix`.
std::vector<std::string> linesStartingWith(const std::string& text, const std::string& prefix);

// A fresh directory under the system temporary directory, removed (with its contents) on
// destruction. Permissions are restored first so that chmod'ed fixtures can be deleted.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return m_path; }
  std::filesystem::path operator/(const std::string& name) const { return m_path / name; }
  // Names of the entries directly inside, sorted.
  std::vector<std::string> entries() const;

 private:
  std::filesystem::path m_path;
};

// runVktg in `dir`, expecting success: exit 0, no validation message and no error line.
CliResult runVktgOk(const std::vector<std::string>& args, const TempDir& dir);

// Every regular file under `dir` with its bytes, and every other entry by name: equal snapshots
// before and after a run mean it created or changed nothing.
std::map<std::string, std::string> directorySnapshot(const TempDir& dir);

std::string readFileBytes(const std::filesystem::path& path);
void writeFileBytes(const std::filesystem::path& path, const std::string& bytes);
// Writes `value` as JSON: the scene, scan and experiment files a test sets up.
void writeJsonFile(const std::filesystem::path& path, const nlohmann::json& value);

}  // namespace vktg::test
