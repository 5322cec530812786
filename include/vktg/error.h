// The one exception type for user-facing errors. Messages read "FILE: FIELD: PROBLEM" so the
// command line can print them as `vktg: error: ...` and exit non-zero.
#pragma once
#include <stdexcept>
#include <string>

namespace vktg {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A run stopped by SIGINT or SIGTERM at a safe point (render/interrupt.h); the command line exits
// with 128 + the signal number.
class Interrupted : public Error {
 public:
  explicit Interrupted(int signal);
  int signal() const { return m_signal; }

 private:
  int m_signal;
};

// Formats "file: field: problem", dropping empty parts.
std::string describeError(const std::string& file, const std::string& field, const std::string& problem);

[[noreturn]] void fail(const std::string& file, const std::string& field, const std::string& problem);

}  // namespace vktg
