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

// Formats "file: field: problem", dropping empty parts.
std::string describeError(const std::string& file, const std::string& field, const std::string& problem);

[[noreturn]] void fail(const std::string& file, const std::string& field, const std::string& problem);

}  // namespace vktg
