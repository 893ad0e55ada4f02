// The exclusive lock on an output folder (flock on the directory itself).
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>

#include "camplace/optimize/report.hpp"

namespace camplace::optimize {

FolderLock::FolderLock(const std::string& dir) {
  // The folder itself is locked (flock works on a directory's descriptor on Linux): no lock
  // file joins the user's files.
  fd_ = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error("cannot open " + dir + ": " + std::strerror(errno));
  while (::flock(fd_, LOCK_EX) != 0) {
    if (errno == EINTR) continue;  // a signal (its flag is seen after the summary is written)
    const int error = errno;
    ::close(fd_);
    throw std::runtime_error("cannot lock " + dir + ": " + std::strerror(error));
  }
}

FolderLock::~FolderLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
}

}  // namespace camplace::optimize
