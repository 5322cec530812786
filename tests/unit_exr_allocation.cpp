// A hostile EXR must be refused before it is allocated for. Two files found by the `experiment`
// fuzz target: 335 bytes declaring a data window 10551304 pixels wide (opening it with OpenEXR sized
// the decompression buffers by that width, 675 MB, before vktg's size check ran), and 481 bytes
// whose channel list declares more bytes than its channels take, with a string-vector attribute
// hidden in the rest: OpenEXR parses the next attribute from where the channels end, and allocated
// the 1.9 GB that string declared. Also a valid file with one length made huge in each kind of
// attribute OpenEXR allocates for. This binary replaces the global operator new to record the
// largest single allocation (OpenEXR's allocations inside its shared library come here too), and
// asserts it stays small.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <new>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfPreviewImage.h>

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

TEST(ExrAllocation, AnAttributeHiddenInsideTheChannelListIsRefusedCheaply) {
  const std::filesystem::path file =
      std::filesystem::path(VKTG_TEST_DATA) / "fuzz" / "exr-attribute-inside-channel-list.exr";
  g_largest = 0;
  test::expectError([&] { readExr(file); },
                    {file.string(), "header", "\"channels\" (chlist)", "channel list ends after 19 of its 124 bytes"});
  EXPECT_LT(g_largest.load(), size_t(1) << 20);
}

class ExrHeaderLengths : public test::TempDirTest {
 protected:
  // The bytes of a valid file, after `edit` has changed them, read back.
  void expectRefused(const std::string& bytes, const std::vector<std::string>& parts) {
    const std::filesystem::path file = m_dir / "edited.exr";
    test::writePlain(file, bytes);
    g_largest = 0;
    std::vector<std::string> all = {file.string(), "header"};
    all.insert(all.end(), parts.begin(), parts.end());
    test::expectError([&] { readExr(file); }, all);
    EXPECT_LT(g_largest.load(), size_t(1) << 20);
  }
  static void putLittleEndian(std::string& bytes, size_t at, uint32_t value) {
    for (int k = 0; k < 4; ++k) bytes[at + size_t(k)] = char((value >> (8 * k)) & 0xff);
  }
  // Where the value of attribute `name` starts (after its name, type and size).
  static size_t valueOf(const std::string& bytes, const std::string& name, const std::string& type) {
    const size_t found = bytes.find(name + std::string(1, '\0') + type + std::string(1, '\0'));
    EXPECT_NE(found, std::string::npos) << name;
    return found + name.size() + type.size() + 2 + 4;
  }
};

TEST_F(ExrHeaderLengths, AStringOfAStringVectorLongerThanItsAttribute) {
  // Two layers: writeExr records their order in a string-vector attribute.
  writeExr(m_dir / "two.exr", ImageSet{1, 1, {{"a", {1.0f}}, {"b", {2.0f}}}});
  std::string bytes = test::readAll(m_dir / "two.exr");
  putLittleEndian(bytes, valueOf(bytes, "vktgLayerOrder", "stringvector"), 0x70000000u);
  expectRefused(bytes, {"\"vktgLayerOrder\" (stringvector)", "string 0 declares 1879048192 bytes"});
}

TEST_F(ExrHeaderLengths, AFixedSizeAttributeDeclaringAnotherSize) {
  writeExr(m_dir / "one.exr", ImageSet{1, 1, {{"", {1.0f}}}});
  std::string bytes = test::readAll(m_dir / "one.exr");
  putLittleEndian(bytes, valueOf(bytes, "compression", "compression") - 4, 2);
  expectRefused(bytes, {"\"compression\" (compression)", "declares 2 bytes, but a compression holds 1"});
}

TEST_F(ExrHeaderLengths, APreviewLargerThanItsAttribute) {
  Imf::Header header(1, 1);
  header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
  header.setPreviewImage(Imf::PreviewImage(2, 2));
  const std::filesystem::path file = m_dir / "preview.exr";
  {
    Imf::OutputFile out(file.c_str(), header);
  }
  std::string bytes = test::readAll(file);
  putLittleEndian(bytes, valueOf(bytes, "preview", "preview"), 65535);
  putLittleEndian(bytes, valueOf(bytes, "preview", "preview") + 4, 65535);
  expectRefused(bytes, {"\"preview\" (preview)", "65535 x 65535 preview needs 4294836225 pixels of 4 bytes"});
  // 2^31 x 2^31 pixels of 4 bytes are 2^64 bytes: a byte count would wrap to 0 and pass.
  putLittleEndian(bytes, valueOf(bytes, "preview", "preview"), 1u << 31);
  putLittleEndian(bytes, valueOf(bytes, "preview", "preview") + 4, 1u << 31);
  expectRefused(bytes, {"\"preview\" (preview)", "2147483648 x 2147483648 preview needs 4611686018427387904 pixels"});
}

}  // namespace
}  // namespace vktg
