#include "core/util/atomic_file.h"

#include "core/util/io_error.h"

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <string>
#include <unistd.h>

namespace fs = std::filesystem;

namespace glintlab {

fs::path temp_path_beside(const fs::path& path) {
  static std::atomic<unsigned> counter{0};
  fs::path tmp = path;
  tmp += ".tmp" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  return tmp;
}

void write_file_atomic(const fs::path& path, const std::function<void(const fs::path& tmp)>& write) {
  const fs::path tmp = temp_path_beside(path);
  auto discard = [&] {
    std::error_code ec;
    fs::remove(tmp, ec);
  };
  try {
    write(tmp);
  } catch (...) {
    discard();
    throw;
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    discard();
    throw IoError(path.string() + ": cannot replace it with the finished temporary file (" + ec.message() + ")");
  }
}

void write_text_atomic(const fs::path& path, std::string_view bytes) {
  write_file_atomic(path, [&](const fs::path& tmp) {
    int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) throw IoError(tmp.string() + ": cannot create (" + std::strerror(errno) + ")");
    size_t done = 0;
    while (done < bytes.size()) {
      ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        std::string why = std::strerror(errno);
        ::close(fd);
        throw IoError(tmp.string() + ": cannot write (" + why + ")");
      }
      done += size_t(n);
    }
    if (::fsync(fd) != 0 || ::close(fd) != 0)
      throw IoError(tmp.string() + ": cannot flush (" + std::strerror(errno) + ")");
  });
}

}  // namespace glintlab
