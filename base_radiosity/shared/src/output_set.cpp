// Outputs as a set (see hr/output_set.h).
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <hr/output.h>
#include <hr/output_set.h>
#include <set>
#include <sstream>

namespace hr {

namespace fs = std::filesystem;

namespace {

constexpr const char* kPrefix = ".ghr-staging-";
constexpr const char* kCommit = "COMMIT";

/// An exclusive flock on the folder itself (no lock file is left behind).
class DirLock {
 public:
  explicit DirLock(const std::string& dir) : fd_(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)) {
    if (fd_ >= 0) ::flock(fd_, LOCK_EX);
  }
  ~DirLock() {
    if (fd_ >= 0) ::close(fd_);  // closing releases the lock
  }
  DirLock(const DirLock&) = delete;
  DirLock& operator=(const DirLock&) = delete;

 private:
  int fd_;
};

bool alive(long pid) { return pid > 0 && pid != ::getpid() && (::kill(pid_t(pid), 0) == 0 || errno == EPERM); }

std::vector<std::string> readCommit(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> names;
  for (std::string n; std::getline(in, n);)
    if (!n.empty() && n.find('/') == std::string::npos) names.push_back(n);
  return names;
}

/// Completes a committed staging folder, else removes it; the folder itself goes in both cases.
void settle(const fs::path& dir, const fs::path& staging) {
  std::error_code ec;
  if (fs::exists(staging / kCommit, ec))
    for (const std::string& n : readCommit(staging / kCommit))
      if (fs::exists(staging / n, ec)) fs::rename(staging / n, dir / n);  // throws: the set must complete
  fs::remove_all(staging, ec);
}

void recoverLocked(const fs::path& dir) {
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::string name = it->path().filename().string();
    if (name.rfind(kPrefix, 0) != 0) continue;
    char* e = nullptr;
    long pid = std::strtol(name.c_str() + std::strlen(kPrefix), &e, 10);
    if (alive(pid)) continue;  // another run is writing its set right now
    settle(dir, it->path());
  }
}

bool plainName(const std::string& n) { return !n.empty() && n != "." && n != ".." && n.find('/') == std::string::npos; }

}  // namespace

void recoverOutputs(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return;
  DirLock lock(dir);
  recoverLocked(dir);
}

OutputSet::OutputSet(std::string dir, std::vector<std::string> names, std::string flag)
    : dir_(std::move(dir)), flag_(std::move(flag)), names_(std::move(names)) {
  std::set<std::string> unique;
  for (const std::string& n : names_)
    if (!plainName(n) || !unique.insert(n).second) throw std::logic_error("output set: bad or repeated name " + n);
  if (dir_.empty()) dir_.push_back('.');  // the current folder (GCC 12 warns falsely on = ".")
  std::error_code ec;
  fs::file_status st = fs::status(dir_, ec);
  if (fs::exists(st) && !fs::is_directory(st))
    throw InputError(flag_ + ": " + dir_ + " exists and is not a folder");
  if (!fs::exists(st)) {
    // The nearest existing ancestor must be a folder we may create the output folder in.
    fs::path up = fs::absolute(dir_, ec).parent_path();
    while (!up.empty() && !fs::exists(up, ec) && up != up.parent_path()) up = up.parent_path();
    if (!fs::is_directory(up, ec) || ::access(up.c_str(), W_OK | X_OK) != 0)
      throw InputError(flag_ + ": cannot create the output folder " + dir_ + " (" + up.string() + " is not a writable folder)");
    return;
  }
  if (::access(dir_.c_str(), W_OK | X_OK) != 0) throw InputError(flag_ + ": the output folder " + dir_ + " is not writable");
  recoverOutputs(dir_);
  for (const std::string& n : names_) {
    fs::path p = fs::path(dir_) / n;
    fs::file_status t = fs::symlink_status(p, ec);
    if (fs::exists(t) && !fs::is_regular_file(t))
      throw InputError(flag_ + ": " + p.string() + " exists and is not a regular file: the outputs could not replace it");
  }
}

OutputSet::~OutputSet() {
  if (committed_ || staging_.empty()) return;
  std::error_code ec;
  fs::remove_all(staging_, ec);
}

std::string OutputSet::path(const std::string& name) {
  if (std::find(names_.begin(), names_.end(), name) == names_.end())
    throw std::logic_error("output set: " + name + " was not announced");
  if (staging_.empty()) {
    std::error_code ec;
    fs::create_directories(dir_, ec);
    if (ec) throw InputError(flag_ + ": cannot create the output folder " + dir_ + ": " + ec.message());
    std::string folder = kPrefix;
    folder += std::to_string(::getpid());  // not kPrefix + ...: GCC 12 warns falsely (-Wrestrict)
    staging_ = (fs::path(dir_) / folder).string();
    fs::remove_all(staging_, ec);
    fs::create_directory(staging_, ec);
    if (ec) throw std::runtime_error(staging_ + ": cannot create the staging folder: " + ec.message());
  }
  return (fs::path(staging_) / name).string();
}

void OutputSet::commit() {
  if (staging_.empty()) path(names_.front());
  std::ostringstream list;
  for (const std::string& n : names_) {
    if (!fs::is_regular_file(fs::path(staging_) / n)) throw std::logic_error("output set: " + n + " was not written");
    list << n << "\n";
  }
  DirLock lock(dir_);
  // Checked again right before the first rename: nothing may have taken a name since the start.
  for (const std::string& n : names_) {
    std::error_code ec;
    fs::file_status t = fs::symlink_status(fs::path(dir_) / n, ec);
    if (fs::exists(t) && !fs::is_regular_file(t))
      throw InputError(flag_ + ": " + (fs::path(dir_) / n).string() + " exists and is not a regular file");
  }
  writeFileAtomically((fs::path(staging_) / kCommit).string(), list.str());
  settle(dir_, staging_);
  committed_ = true;
}

std::vector<std::string> OutputSet::finalPaths() const {
  std::vector<std::string> out;
  for (const std::string& n : names_) out.push_back((fs::path(dir_) / n).string());
  return out;
}

}  // namespace hr
