#include "support/cli_runner.h"

#include <gtest/gtest.h>

#include "support/file_permissions.h"
#include "support/test_environment.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

extern char** environ;

namespace vktg::test {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void throwErrno(const std::string& what) {
  throw std::runtime_error("cli_runner: " + what + ": " + std::strerror(errno));
}

// The child's environment: ours with `overrides` replacing or adding entries.
std::vector<std::string> childEnvironment(const std::map<std::string, std::string>& overrides) {
  std::vector<std::string> env;
  for (char** e = environ; *e; ++e) {
    std::string entry = *e;
    std::string name = entry.substr(0, entry.find('='));
    if (!overrides.count(name)) env.push_back(entry);
  }
  for (const auto& [name, value] : overrides) env.push_back(name + "=" + value);
  return env;
}

std::vector<char*> pointers(std::vector<std::string>& strings) {
  std::vector<char*> p;
  for (std::string& s : strings) p.push_back(s.data());
  p.push_back(nullptr);
  return p;
}

}  // namespace

std::string CliResult::describe() const {
  std::ostringstream s;
  if (timedOut) s << "timed out after " << seconds << " s (killed)";
  else if (exited) s << "exit " << exitCode;
  else s << "signal " << signal << " (" << strsignal(signal) << ")";
  s << "\n--- stdout ---\n" << out << "\n--- stderr ---\n" << err << "\n---";
  return s.str();
}

CliResult runVktg(const std::vector<std::string>& args, const CliOptions& options) {
  std::vector<std::string> argv = {VKTG_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  return runProgram(argv, options);
}

CliResult runProgram(const std::vector<std::string>& program, const CliOptions& options) {
  applyTestEnvironment();  // the child inherits the test driver selection
  std::vector<std::string> argv = program;
  std::map<std::string, std::string> overrides = {{"VKTG_VALIDATION", "1"}};
  for (const auto& [name, value] : options.env) overrides[name] = value;
  std::vector<std::string> env = childEnvironment(overrides);
  std::vector<char*> argvPointers = pointers(argv), envPointers = pointers(env);
  const std::string cwd = options.cwd.string();

  int outPipe[2], errPipe[2];
  if (pipe2(outPipe, O_CLOEXEC) != 0 || pipe2(errPipe, O_CLOEXEC) != 0) throwErrno("pipe");
  const auto start = std::chrono::steady_clock::now();
  pid_t pid = fork();
  if (pid < 0) throwErrno("fork");
  if (pid == 0) {
    // Child: only async-signal-safe calls until exec. Its own process group, so a timeout kills
    // anything it started too.
    setpgid(0, 0);
    dup2(outPipe[1], STDOUT_FILENO);
    dup2(errPipe[1], STDERR_FILENO);
    int devNull = open("/dev/null", O_RDONLY);
    if (devNull >= 0) dup2(devNull, STDIN_FILENO);
    if (!cwd.empty() && chdir(cwd.c_str()) != 0) _exit(126);
    if (options.enforcePermissions && !dropFileOverrideForExec()) _exit(125);
    execve(argvPointers[0], argvPointers.data(), envPointers.data());
    _exit(127);
  }
  setpgid(pid, pid);  // also from the parent, so kill(-pid) works whichever runs first
  close(outPipe[1]);
  close(errPipe[1]);

  CliResult result;
  const auto deadline = start + std::chrono::duration<double>(options.timeoutSeconds);
  pollfd fds[2] = {{outPipe[0], POLLIN, 0}, {errPipe[0], POLLIN, 0}};
  std::string* sinks[2] = {&result.out, &result.err};
  int openCount = 2;
  bool signalled = false;
  while (openCount > 0) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      result.timedOut = true;
      kill(-pid, SIGKILL);
      break;
    }
    int ready = poll(fds, 2, int(std::min<long long>(left.count(), 1000)));
    if (ready < 0 && errno != EINTR) throwErrno("poll");
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || !(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      char buffer[4096];
      ssize_t n = read(fds[i].fd, buffer, sizeof buffer);
      if (n > 0) {
        sinks[i]->append(buffer, size_t(n));
        if (!signalled && !options.signalWhen.empty() && result.err.find(options.signalWhen) != std::string::npos) {
          kill(pid, options.signal);
          signalled = true;
        }
      } else if (n == 0 || errno != EINTR) {
        close(fds[i].fd);
        fds[i].fd = -1;
        --openCount;
      }
    }
  }
  for (auto& fd : fds)
    if (fd.fd >= 0) close(fd.fd);

  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throwErrno("waitpid");
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (WIFEXITED(status)) {
    result.exited = !result.timedOut;
    result.exitCode = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    result.signal = WTERMSIG(status);
  }
  if (result.exited && result.exitCode == 127) throw std::runtime_error("cli_runner: cannot execute " + argv[0]);
  return result;
}

std::vector<std::string> linesStartingWith(const std::string& text, const std::string& prefix) {
  std::vector<std::string> lines;
  std::istringstream stream(text);
  std::string line;
  while (std::getline(stream, line))
    if (line.rfind(prefix, 0) == 0) lines.push_back(line);
  return lines;
}

TempDir::TempDir() {
  static std::atomic<unsigned> counter{0};
  for (int attempt = 0; attempt < 100; ++attempt) {
    fs::path candidate = fs::temp_directory_path() /
                         ("vktg-cli-" + std::to_string(getpid()) + "-" + std::to_string(counter++));
    std::error_code error;
    if (fs::create_directory(candidate, error)) {
      m_path = candidate;
      return;
    }
  }
  throw std::runtime_error("cli_runner: cannot create a temporary directory");
}

TempDir::~TempDir() {
  std::error_code error;
  for (const auto& entry : fs::recursive_directory_iterator(m_path, error))
    fs::permissions(entry.path(), fs::perms::owner_all, fs::perm_options::add, error);
  fs::remove_all(m_path, error);
}

std::vector<std::string> TempDir::entries() const {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(m_path)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::map<std::string, std::string> directorySnapshot(const TempDir& dir) {
  std::map<std::string, std::string> state;
  for (const auto& entry : fs::recursive_directory_iterator(dir.path())) {
    const std::string name = fs::relative(entry.path(), dir.path()).string();
    std::error_code error;
    if (entry.is_symlink()) state[name] = "<symlink to " + fs::read_symlink(entry.path()).string() + ">";
    else if (entry.is_regular_file(error) && ::access(entry.path().c_str(), R_OK) == 0) state[name] = readFileBytes(entry.path());
    else state[name] = "<not read>";
  }
  return state;
}

std::string readFileBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

void writeFileBytes(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

void writeJsonFile(const fs::path& path, const nlohmann::json& value) { writeFileBytes(path, value.dump(1)); }

CliResult runVktgOk(const std::vector<std::string>& args, const TempDir& dir) {
  CliResult r = runVktg(args, {.cwd = dir.path()});
  EXPECT_TRUE(r.exited && r.exitCode == 0) << r.describe();
  EXPECT_EQ(r.err.find("vktg: validation:"), std::string::npos) << r.describe();
  EXPECT_TRUE(linesStartingWith(r.err, "vktg: error:").empty()) << r.describe();
  return r;
}

}  // namespace vktg::test
