// The name gtest prints for one row of a table-driven test (INSTANTIATE_TEST_SUITE_P's fourth
// argument): the row's `name` with every character gtest does not allow replaced by '_'
// (header-only: `unit` tests link no test-support library).
#pragma once
#include <cctype>
#include <string>

#include <gtest/gtest.h>

namespace vktg::test {

template <typename Case>
std::string tableCaseName(const testing::TestParamInfo<Case>& info) {
  std::string name = info.param.name;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

}  // namespace vktg::test
