// posix_spawn rather than std::system: no shell, so a scene path with spaces or quotes is passed as
// it is, and the exit status is the child's own.
#include "child.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

extern char** environ;

namespace study {

ScratchDir::ScratchDir(const std::string& what)
    : path_(std::filesystem::temp_directory_path() / ("glossyhr-" + what + "-" + std::to_string(::getpid()))) {
  std::filesystem::create_directories(path_);
}

ScratchDir::~ScratchDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

ChildResult run(const std::string& program, const std::vector<std::string>& args, const std::string& logPath,
                const std::string& image) {
  std::vector<std::string> all = {program};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, logPath.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  auto t0 = std::chrono::steady_clock::now();
  pid_t pid = 0;
  int rc = image.empty() ? posix_spawnp(&pid, program.c_str(), &fa, nullptr, argv.data(), environ)
                         : posix_spawn(&pid, image.c_str(), &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) throw std::runtime_error("cannot start " + program + ": " + std::strerror(rc));
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
  ChildResult r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

ChildResult runSelf(const std::vector<std::string>& args, const std::string& logPath) {
  // The child's /proc/self/exe, resolved as it execs, is still the parent's image (it is a copy of the
  // parent until then); by name, a rebuild mid-study made every later configuration fail to start.
  return run(std::filesystem::read_symlink("/proc/self/exe").string(), args, logPath, "/proc/self/exe");
}

std::string failureReason(const std::string& logPath) {
  std::ifstream in(logPath);
  std::string line, first;
  while (std::getline(in, line)) {
    if (line.rfind("error", 0) == 0 || line.rfind("internal error", 0) == 0) return line;
    if (first.empty() && !line.empty() && line.rfind("warning", 0) != 0 && line.rfind("note", 0) != 0) first = line;
  }
  return first.empty() ? "no output" : first;
}

}  // namespace study
