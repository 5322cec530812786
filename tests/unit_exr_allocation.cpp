// A hostile EXR must be refused before it is allocated for: a 335-byte file found by the
// `experiment` fuzz target declares a data window 10551304 pixels wide, and opening it with
// OpenEXR sized the decompression buffers by that width (675 MB) before vktg's size check ran.
// This binary replaces the global operator new to record the largest single allocation (OpenEXR's
// allocations inside its shared library come here too), and asserts it stays small.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <new>

#include "support/file_test.h"
#include "vktg/image_io.h"

namespace {
std::atomic<size_t> g_largest{0};

void* allocate(size_t size) {
  size_t seen = g_largest.load();
  while (size > seen && !g_largest.compare_exchange_weak(seen, size)) {
  }
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(size_t size) { return allocate(size); }
void* operator new[](size_t size) { return allocate(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, size_t) noexcept { std::free(p); }
void operator delete[](void* p, size_t) noexcept { std::free(p); }

namespace vktg {
namespace {

TEST(ExrAllocation, AHugeDeclaredDataWindowIsRefusedBeforeAnyLargeAllocation) {
  const std::filesystem::path file = std::filesystem::path(VKTG_TEST_DATA) / "fuzz" / "exr-huge-data-window.exr";
  ASSERT_LT(std::filesystem::file_size(file), 400u);
  g_largest = 0;
  test::expectError([&] { readExr(file); }, {file.string(), "dataWindow", "image too large (10551304x8)"});
  EXPECT_LT(g_largest.load(), size_t(1) << 20) << "the largest allocation while reading a 335-byte file";
}

}  // namespace
}  // namespace vktg
