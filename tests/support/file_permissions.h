// Permission-denied cases that also run as root (CI containers run the suite as root, which the
// kernel lets read and write any file). Root bypasses file permissions only through two
// capabilities, CAP_DAC_OVERRIDE and CAP_DAC_READ_SEARCH; without them it is refused like any
// owner whose permission bits say no. Header-only: `unit` tests link no test-support library.
// Capabilities belong to a thread and cannot be regained once dropped from the permitted set, so
// in-process checks run in a forked child and command-line runs drop them before exec.
#pragma once
#include <linux/capability.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>

#include "vktg/error.h"

namespace vktg::test {

inline constexpr int kFileOverrideCapabilities[] = {CAP_DAC_OVERRIDE, CAP_DAC_READ_SEARCH};

// What a body run by runWithoutFileOverride did.
struct ChildOutcome {
  bool ran = false;    // false: the capabilities could not be dropped (the test cannot enforce permissions)
  bool threw = false;  // it threw vktg::Error ...
  std::string message;  // ... with this message
};

// Runs `body` in a forked child that has neither capability, not even in its permitted set (so
// access(2), which consults the permitted set for root, obeys the permission bits too).
template <typename Body>
ChildOutcome runWithoutFileOverride(Body body) {
  int pipeFds[2];
  if (pipe(pipeFds) != 0) return {};
  const pid_t pid = fork();
  if (pid < 0) return {};
  if (pid == 0) {
    close(pipeFds[0]);
    if (::geteuid() == 0) {
      __user_cap_header_struct header{_LINUX_CAPABILITY_VERSION_3, 0};
      __user_cap_data_struct data[2]{};
      if (syscall(SYS_capget, &header, data) != 0) _exit(3);
      for (int cap : kFileOverrideCapabilities)
        for (auto* set : {&data[cap / 32].effective, &data[cap / 32].permitted, &data[cap / 32].inheritable})
          *set &= ~(1u << (cap % 32));
      if (syscall(SYS_capset, &header, data) != 0) _exit(3);
    }
    int status = 1;
    std::string message;
    try {
      body();
    } catch (const vktg::Error& e) {
      message = e.what();
      status = 0;
    } catch (...) {
      status = 2;
    }
    if (write(pipeFds[1], message.data(), message.size()) < 0) status = 4;
    _exit(status);
  }
  close(pipeFds[1]);
  std::string message;
  char buffer[512];
  for (ssize_t n; (n = read(pipeFds[0], buffer, sizeof buffer)) > 0;) message.append(buffer, size_t(n));
  close(pipeFds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (code == 3) return {};
  return {true, code == 0, message};
}

// Whether a child can be made to run without them (dropFileOverrideForExec needs CAP_SETPCAP).
inline bool canDropFileOverrideForExec() {
  if (::geteuid() != 0) return true;
  __user_cap_header_struct header{_LINUX_CAPABILITY_VERSION_3, 0};
  __user_cap_data_struct data[2]{};
  return syscall(SYS_capget, &header, data) == 0 && (data[CAP_SETPCAP / 32].effective & (1u << (CAP_SETPCAP % 32)));
}

// For a child about to exec (async-signal-safe): removes both capabilities from its bounding set,
// so the program it runs never gets them, even as root. Returns false if that was refused.
inline bool dropFileOverrideForExec() {
  if (::geteuid() != 0) return true;
  for (int cap : kFileOverrideCapabilities)
    if (prctl(PR_CAPBSET_DROP, cap, 0, 0, 0) != 0) return false;
  return true;
}

}  // namespace vktg::test
