// Helpers of the CPU-only file tests (header-only: `unit` tests link no test-support library).
#pragma once
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "vktg/error.h"

namespace vktg::test {

inline std::string readAll(const std::filesystem::path& path) {
  std::ifstream stream(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(stream)), std::istreambuf_iterator<char>());
}

// Writes without vktg's atomic writer (the tests set up files the code under test then reads).
inline void writePlain(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream stream(path, std::ios::binary);
  stream << bytes;
}

// Runs `body`, expecting a vktg::Error whose message contains every string in `parts`.
template <typename Body>
void expectError(Body body, const std::vector<std::string>& parts) {
  try {
    body();
    FAIL() << "expected vktg::Error";
  } catch (const vktg::Error& error) {
    for (const std::string& part : parts)
      EXPECT_NE(std::string(error.what()).find(part), std::string::npos)
          << "message '" << error.what() << "' lacks '" << part << "'";
  }
}

// A fixture with a fresh directory per test (unique across concurrent test processes), removed
// afterwards.
class TempDirTest : public testing::Test {
 protected:
  void SetUp() override {
    m_dir = std::filesystem::temp_directory_path() /
            ("vktg-" + std::string(testing::UnitTest::GetInstance()->current_test_info()->test_suite_name()) + "-" +
             std::to_string(::getpid()) + "-" + std::to_string(std::random_device{}()));
    std::filesystem::create_directories(m_dir);
  }
  void TearDown() override {
    std::error_code error;
    std::filesystem::remove_all(m_dir, error);
  }
  std::filesystem::path m_dir;
};

}  // namespace vktg::test
