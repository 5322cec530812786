#include "vktg/error.h"

namespace vktg {

std::string describeError(const std::string& file, const std::string& field, const std::string& problem) {
  std::string out;
  for (const std::string* part : {&file, &field}) {
    if (part->empty()) continue;
    out += *part;
    out += ": ";
  }
  return out + problem;
}

void fail(const std::string& file, const std::string& field, const std::string& problem) {
  throw Error(describeError(file, field, problem));
}

}  // namespace vktg
