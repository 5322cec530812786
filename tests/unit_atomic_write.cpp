// Atomic writes and output-path checks: a failed write must leave the previous file untouched and
// no temporary files behind, and an output may never be one of the command's inputs.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

#include "vktg/error.h"
#include "support/file_permissions.h"
#include "support/file_test.h"
#include "vktg/image_io.h"

namespace fs = std::filesystem;

namespace {

using vktg::test::expectError;
using vktg::test::ChildOutcome;
using vktg::test::runWithoutFileOverride;

// A body run by runWithoutFileOverride threw a vktg::Error whose message contains every part.
void expectChildError(const ChildOutcome& child, const std::vector<std::string>& parts) {
  EXPECT_TRUE(child.threw) << "expected vktg::Error";
  for (const std::string& part : parts)
    EXPECT_NE(child.message.find(part), std::string::npos) << "message '" << child.message << "' lacks '" << part << "'";
}
using vktg::test::readAll;
using vktg::test::writePlain;

std::vector<std::string> listDirectory(const fs::path& directory) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(directory)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

class AtomicWrite : public ::testing::Test {
 protected:
  void SetUp() override {
    m_dir = fs::temp_directory_path() /
            ("vktg-unit-atomic-" + std::to_string(::getpid()) + "-" + std::to_string(std::random_device{}()));
    fs::create_directories(m_dir);
  }
  void TearDown() override {
    std::error_code error;
    fs::permissions(m_dir, fs::perms::owner_all, fs::perm_options::add, error);
    for (const auto& entry : fs::recursive_directory_iterator(m_dir, error)) {
      if (entry.is_directory()) fs::permissions(entry.path(), fs::perms::owner_all, fs::perm_options::add, error);
    }
    fs::remove_all(m_dir, error);
  }
  fs::path m_dir;
};

TEST_F(AtomicWrite, WritesExactBytes) {
  const std::string bytes("binary\0data\xff\n", 13);
  vktg::writeFileAtomic(m_dir / "out.bin", bytes);
  EXPECT_EQ(readAll(m_dir / "out.bin"), bytes);
  EXPECT_EQ(listDirectory(m_dir), std::vector<std::string>{"out.bin"});
}

TEST_F(AtomicWrite, ReplacesExistingFileCompletely) {
  writePlain(m_dir / "out.txt", std::string(1000, 'x'));
  vktg::writeFileAtomic(m_dir / "out.txt", "short");
  EXPECT_EQ(readAll(m_dir / "out.txt"), "short");
  EXPECT_EQ(listDirectory(m_dir), std::vector<std::string>{"out.txt"});
}

TEST_F(AtomicWrite, MissingDirectoryThrowsAndCreatesNothing) {
  const fs::path target = m_dir / "missing" / "out.txt";
  expectError([&] { vktg::writeFileAtomic(target, "data"); }, {target.string(), "does not exist"});
  EXPECT_FALSE(fs::exists(m_dir / "missing"));
  EXPECT_TRUE(listDirectory(m_dir).empty());
}

TEST_F(AtomicWrite, TargetThatIsADirectoryThrows) {
  fs::create_directory(m_dir / "sub");
  expectError([&] { vktg::writeFileAtomic(m_dir / "sub", "data"); }, {(m_dir / "sub").string(), "directory"});
  EXPECT_TRUE(fs::is_directory(m_dir / "sub"));
  EXPECT_TRUE(listDirectory(m_dir / "sub").empty());
}

TEST_F(AtomicWrite, ReadOnlyDirectoryKeepsPreviousFile) {
  writePlain(m_dir / "out.txt", "previous");
  fs::permissions(m_dir, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                             fs::perms::group_exec | fs::perms::others_read | fs::perms::others_exec);
  // Without the permission override, so that the directory is read-only for root too.
  ChildOutcome child = runWithoutFileOverride([&] { vktg::writeFileAtomic(m_dir / "out.txt", "new"); });
  if (!child.ran) GTEST_SKIP() << "running as root and cannot drop CAP_DAC_OVERRIDE";
  expectChildError(child, {(m_dir / "out.txt").string(), "permission denied"});
  EXPECT_EQ(readAll(m_dir / "out.txt"), "previous");
  EXPECT_EQ(listDirectory(m_dir), std::vector<std::string>{"out.txt"});
}

// A write that fails half-way (file size limit exceeded; works as root too) must leave the old
// file intact and remove its temporary file.
TEST_F(AtomicWrite, FailureMidWriteKeepsPreviousFileAndLeavesNoTemp) {
  writePlain(m_dir / "out.txt", "previous");
  rlimit original{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &original), 0);
  rlimit limited = original;
  limited.rlim_cur = 4096;
  auto* previousHandler = std::signal(SIGXFSZ, SIG_IGN);
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limited), 0);
  bool threw = false;
  std::string message;
  try {
    vktg::writeFileAtomic(m_dir / "out.txt", std::string(1 << 20, 'z'));
  } catch (const vktg::Error& error) {
    threw = true;
    message = error.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &original);
  std::signal(SIGXFSZ, previousHandler);
  EXPECT_TRUE(threw);
  EXPECT_NE(message.find((m_dir / "out.txt").string()), std::string::npos) << message;
  EXPECT_EQ(readAll(m_dir / "out.txt"), "previous");
  EXPECT_EQ(listDirectory(m_dir), std::vector<std::string>{"out.txt"});
}

// Concurrent writers to one target each use their own temporary file, so the result is exactly
// one of the complete contents.
TEST_F(AtomicWrite, ConcurrentWritersNeverMix) {
  const std::string a(200000, 'a'), b(300000, 'b');
  std::thread first([&] { for (int i = 0; i < 20; ++i) vktg::writeFileAtomic(m_dir / "out.txt", a); });
  std::thread second([&] { for (int i = 0; i < 20; ++i) vktg::writeFileAtomic(m_dir / "out.txt", b); });
  first.join();
  second.join();
  const std::string result = readAll(m_dir / "out.txt");
  EXPECT_TRUE(result == a || result == b);
  EXPECT_EQ(listDirectory(m_dir), std::vector<std::string>{"out.txt"});
}

class CheckOutputPath : public AtomicWrite {};

TEST_F(CheckOutputPath, AcceptsNewFileInWritableDirectory) {
  writePlain(m_dir / "in.json", "{}");
  EXPECT_NO_THROW(vktg::checkOutputPath(m_dir / "out.exr", {m_dir / "in.json"}));
  writePlain(m_dir / "out.exr", "old");
  EXPECT_NO_THROW(vktg::checkOutputPath(m_dir / "out.exr", {m_dir / "in.json"}));
}

TEST_F(CheckOutputPath, RefusesOutputEqualToInput) {
  writePlain(m_dir / "in.exr", "data");
  expectError([&] { vktg::checkOutputPath(m_dir / "in.exr", {m_dir / "other.json", m_dir / "in.exr"}); },
              {(m_dir / "in.exr").string(), "input"});
}

TEST_F(CheckOutputPath, RefusesDifferentSpellingOfInput) {
  fs::create_directory(m_dir / "sub");
  writePlain(m_dir / "sub" / "in.exr", "data");
  const fs::path spelled = m_dir / "sub" / ".." / "sub" / "." / "in.exr";
  expectError([&] { vktg::checkOutputPath(spelled, {m_dir / "sub" / "in.exr"}); }, {spelled.string()});
  // Relative to the working directory.
  const fs::path previous = fs::current_path();
  fs::current_path(m_dir);
  bool threw = false;
  try {
    vktg::checkOutputPath("sub/in.exr", {m_dir / "sub" / "in.exr"});
  } catch (const vktg::Error&) {
    threw = true;
  }
  fs::current_path(previous);
  EXPECT_TRUE(threw);
}

TEST_F(CheckOutputPath, RefusesSymlinkAndHardLinkToInput) {
  writePlain(m_dir / "in.exr", "data");
  fs::create_symlink(m_dir / "in.exr", m_dir / "link.exr");
  fs::create_hard_link(m_dir / "in.exr", m_dir / "hard.exr");
  expectError([&] { vktg::checkOutputPath(m_dir / "link.exr", {m_dir / "in.exr"}); }, {(m_dir / "link.exr").string()});
  expectError([&] { vktg::checkOutputPath(m_dir / "hard.exr", {m_dir / "in.exr"}); }, {(m_dir / "hard.exr").string()});
  // Through a symlinked directory.
  fs::create_directory_symlink(m_dir, m_dir / "alias");
  expectError([&] { vktg::checkOutputPath(m_dir / "alias" / "in.exr", {m_dir / "in.exr"}); }, {"in.exr"});
}

TEST_F(CheckOutputPath, RefusesSamePathEvenWhenInputDoesNotExistYet) {
  expectError([&] { vktg::checkOutputPath(m_dir / "x" / ".." / "a.exr", {m_dir / "a.exr"}); }, {"a.exr"});
}

TEST_F(CheckOutputPath, RefusesMissingDirectory) {
  const fs::path target = m_dir / "missing" / "out.exr";
  expectError([&] { vktg::checkOutputPath(target, {}); }, {target.string(), "does not exist"});
}

TEST_F(CheckOutputPath, RefusesDirectoryAsOutput) {
  fs::create_directory(m_dir / "sub");
  expectError([&] { vktg::checkOutputPath(m_dir / "sub", {}); }, {(m_dir / "sub").string(), "directory"});
}

TEST_F(CheckOutputPath, RefusesReadOnlyDirectory) {
  fs::create_directory(m_dir / "ro");
  fs::permissions(m_dir / "ro", fs::perms::owner_read | fs::perms::owner_exec);
  ChildOutcome child = runWithoutFileOverride([&] { vktg::checkOutputPath(m_dir / "ro" / "out.exr", {}); });
  if (!child.ran) GTEST_SKIP() << "running as root and cannot drop CAP_DAC_OVERRIDE";
  expectChildError(child, {(m_dir / "ro" / "out.exr").string(), "not writable"});
}

}  // namespace
