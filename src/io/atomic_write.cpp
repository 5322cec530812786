// Atomic file replacement: the bytes go to a uniquely named temporary file in the destination
// directory (same file system, so rename(2) is atomic) and are renamed over the target only once
// fully written and flushed. Readers therefore see either the old file or the complete new one.
#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <random>

#include "io/io_internal.h"
#include "vktg/error.h"

namespace vktg {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void failWrite(const fs::path& path, const std::string& reason) {
  fail(path.string(), "", "cannot write: " + reason);
}

// Closes the descriptor and removes the temporary file unless the write was committed.
class TempFile {
 public:
  TempFile(const fs::path& target, const fs::path& directory) : m_target(target) {
    // pid + process-wide counter + random suffix: unique across threads and concurrent processes;
    // O_EXCL still guards against the unlikely collision with a leftover file.
    static std::atomic<uint64_t> counter{0};
    std::random_device entropy;
    for (int attempt = 0; attempt < 100; ++attempt) {
      std::string name = ".";
      name += target.filename().string();
      name += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "-" + std::to_string(entropy());
      m_path = directory / name;
      // 0666 filtered by the umask gives the permissions an ordinary newly created file would have.
      m_fd = ::open(m_path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (m_fd >= 0) return;
      if (errno != EEXIST) failWrite(m_target, io::describeErrno(errno));
    }
    failWrite(m_target, "could not create a unique temporary file in '" + directory.string() + "'");
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  ~TempFile() {
    if (m_fd >= 0) ::close(m_fd);
    if (!m_committed) ::unlink(m_path.c_str());
  }

  void write(const std::string& bytes) {
    const char* data = bytes.data();
    size_t left = bytes.size();
    while (left > 0) {
      const ssize_t written = ::write(m_fd, data, left);
      if (written < 0) {
        if (errno == EINTR) continue;
        failWrite(m_target, io::describeErrno(errno));
      }
      data += written;
      left -= size_t(written);
    }
    // Flush before the rename so a crash cannot leave a renamed but empty file behind.
    if (::fsync(m_fd) != 0) failWrite(m_target, io::describeErrno(errno));
    const int fd = m_fd;
    m_fd = -1;
    if (::close(fd) != 0) failWrite(m_target, io::describeErrno(errno));
  }

  void commit() {
    if (::rename(m_path.c_str(), m_target.c_str()) != 0) failWrite(m_target, io::describeErrno(errno));
    m_committed = true;
  }

 private:
  fs::path m_target;
  fs::path m_path;
  int m_fd = -1;
  bool m_committed = false;
};

}  // namespace

void writeFileAtomic(const fs::path& path, const std::string& bytes) {
  if (path.empty() || !path.has_filename()) failWrite(path, "the path does not name a file");
  const fs::path directory = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  std::error_code error;
  if (!fs::exists(directory, error)) failWrite(path, "directory '" + directory.string() + "' does not exist");
  if (!fs::is_directory(directory, error)) failWrite(path, "'" + directory.string() + "' is not a directory");
  if (fs::is_directory(path, error)) failWrite(path, "it is a directory");
  TempFile temp(path, directory);
  temp.write(bytes);
  temp.commit();
}

}  // namespace vktg
