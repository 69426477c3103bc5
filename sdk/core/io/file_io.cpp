// SPDX-License-Identifier: GPL-3.0-or-later
// Whole-file reading and atomic writing (temporary file beside the target, then rename).
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/io/file_io.h"

#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN
namespace {

[[noreturn]] void fail_os(const std::string& what, const std::string& path, int error) {
  fail(Status::io_error, path + ": " + what + ": " + std::strerror(error));
}

class FileCloser {
 public:
  explicit FileCloser(int fd) : fd_(fd) {}
  ~FileCloser() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileCloser(const FileCloser&) = delete;
  FileCloser& operator=(const FileCloser&) = delete;
  int release() {
    const int fd = fd_;
    fd_ = -1;
    return fd;
  }

 private:
  int fd_;
};

void write_all(int fd, const std::vector<uint8_t>& bytes, const std::string& path) {
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail_os("cannot write", path, n < 0 ? errno : EIO);
    done += static_cast<size_t>(n);
  }
}

// Creates "<path>.tmp-<pid>-<n>" exclusively, mode 0666 minus the umask (as a plain open would).
int create_temporary(const std::string& path, std::string& tmp) {
  static std::atomic<unsigned> counter{0};
  for (int attempt = 0; attempt < 100; ++attempt) {
    tmp = path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0 || errno != EEXIST) return fd;
  }
  errno = EEXIST;
  return -1;
}

}  // namespace

std::vector<uint8_t> read_whole_file(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) fail_os("cannot open", path, errno);
  FileCloser closer(fd);
  struct stat info {};
  if (::fstat(fd, &info) != 0) fail_os("cannot stat", path, errno);
  if (S_ISDIR(info.st_mode)) fail(Status::io_error, path + ": is a directory");
  std::vector<uint8_t> bytes;
  if (S_ISREG(info.st_mode) && info.st_size > 0) bytes.reserve(static_cast<size_t>(info.st_size));
  uint8_t chunk[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, chunk, sizeof(chunk));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail_os("cannot read", path, errno);
    if (n == 0) break;
    bytes.insert(bytes.end(), chunk, chunk + n);
  }
  return bytes;
}

void write_file_atomically(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::string tmp;
  const int fd = create_temporary(path, tmp);
  if (fd < 0) fail_os("cannot create a temporary file beside the output", path, errno);
  FileCloser closer(fd);
  try {
    write_all(fd, bytes, path);
    if (::fsync(fd) != 0) fail_os("cannot flush", path, errno);
    if (::close(closer.release()) != 0) fail_os("cannot close", path, errno);
    if (::rename(tmp.c_str(), path.c_str()) != 0) fail_os("cannot rename the temporary file", path, errno);
  } catch (...) {
    ::unlink(tmp.c_str());
    throw;
  }
}

CAGEKIT_NAMESPACE_END
