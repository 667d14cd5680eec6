// Checked input files. The file is opened first (O_NONBLOCK, so a FIFO does not block the open) and
// then inspected through its descriptor, so the checks apply to what is actually read.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <hr/input_file.h>
#include <hr/types.h>

namespace hr {
namespace {

class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

std::string kindOf(mode_t m) {
  if (S_ISDIR(m)) return "a directory";
  if (S_ISFIFO(m)) return "a FIFO";
  if (S_ISCHR(m)) return "a character device";
  if (S_ISBLK(m)) return "a block device";
  if (S_ISSOCK(m)) return "a socket";
  return "not a regular file";
}

/// Opens path and checks it; returns the descriptor and its size.
int openChecked(const std::string& path, const char* what, std::uint64_t maxBytes, std::uint64_t& size) {
  if (path.empty()) throw InputError(std::string("empty path given for the ") + what);
  int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    int e = errno;
    if (e == ENOENT) throw InputError(path + ": " + what + " does not exist");
    throw InputError(path + ": cannot open " + what + ": " + std::strerror(e));
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    std::string kind = ::fstat(fd, &st) == 0 ? kindOf(st.st_mode) : "unreadable";
    ::close(fd);
    throw InputError(path + ": " + what + " is " + kind + ", not a regular file");
  }
  size = static_cast<std::uint64_t>(st.st_size);
  if (size > maxBytes) {
    ::close(fd);
    throw InputError(path + ": " + what + " is " + std::to_string(size) + " bytes, more than the limit of " +
                     std::to_string(maxBytes));
  }
  return fd;
}

}  // namespace

std::string readInputFile(const std::string& path, const char* what, std::uint64_t maxBytes) {
  std::uint64_t size = 0;
  Fd fd(openChecked(path, what, maxBytes, size));
  std::string data;
  data.resize(static_cast<std::size_t>(size));
  std::size_t got = 0;
  // A file that grows while read is cut at the size it had: the limit holds whatever happens.
  while (got < data.size()) {
    ssize_t n = ::read(fd.get(), data.data() + got, data.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw InputError(path + ": cannot read " + what + ": " + std::strerror(errno));
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  data.resize(got);
  return data;
}

void checkInputFile(const std::string& path, const char* what, std::uint64_t maxBytes) {
  std::uint64_t size = 0;
  Fd fd(openChecked(path, what, maxBytes, size));
}

void stripUtf8Bom(std::string& text) {
  if (text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
}

}  // namespace hr
