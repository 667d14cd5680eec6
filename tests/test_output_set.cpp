// Outputs as a set (hr/output_set.h): a failed run leaves the folder as it was; a killed run's staging
// folder is finished (COMMIT written) or removed (not) by the next start; a live run's staging is left
// alone. Then the kill test: 20 runs of `glossyhr solve` killed with SIGKILL at random moments, half
// anywhere in the run and half while the outputs are written; after each, the folder holds the
// previous set byte for byte or the new set complete, never a mix, and no staging or temporary file.
#include <gtest/gtest.h>
#include <hr/output.h>
#include <hr/output_set.h>
#include <nlohmann/json.hpp>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <thread>

#include "test_dir.h"

namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::map<std::string, std::string> files(const fs::path& dir) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::directory_iterator(dir)) m[e.path().filename().string()] = e.is_regular_file() ? slurp(e.path()) : "<dir>";
  return m;
}

TEST(OutputSet, FailureBeforeCommitLeavesThePreviousFiles) {
  fs::path dir = testutil::testDir();
  std::ofstream(dir / "a.txt") << "old a";
  {
    hr::OutputSet out(dir.string(), {"a.txt", "b.txt"});
    hr::writeFileAtomically(out.path("a.txt"), "new a");
    // b.txt never written: the run fails here (the destructor runs without commit).
  }
  EXPECT_EQ(files(dir), (std::map<std::string, std::string>{{"a.txt", "old a"}}));
}

TEST(OutputSet, CommitReplacesTheWholeSet) {
  fs::path dir = testutil::testDir() / "new";
  hr::OutputSet out(dir.string(), {"a.txt", "b.txt"});
  EXPECT_FALSE(fs::exists(dir)) << "nothing is created before the first output";
  hr::writeFileAtomically(out.path("a.txt"), "new a");
  hr::writeFileAtomically(out.path("b.txt"), "new b");
  out.commit();
  EXPECT_EQ(files(dir), (std::map<std::string, std::string>{{"a.txt", "new a"}, {"b.txt", "new b"}}));
}

/// A staging folder as a run killed at some point would leave it (pid 0x7ffffff0 is never alive).
fs::path fakeStaging(const fs::path& dir, bool committed, const std::vector<std::string>& present) {
  fs::path st = dir / ".ghr-staging-2147483632";
  fs::create_directories(st);
  for (const auto& n : present) std::ofstream(st / n) << "new " + n.substr(0, 1);
  if (committed) std::ofstream(st / "COMMIT") << "a.txt\nb.txt\n";
  return st;
}

TEST(OutputSet, NextStartRemovesAnUncommittedStaging) {
  fs::path dir = testutil::testDir();
  std::ofstream(dir / "a.txt") << "old a";
  std::ofstream(dir / "b.txt") << "old b";
  fakeStaging(dir, false, {"a.txt"});
  hr::recoverOutputs(dir.string());
  EXPECT_EQ(files(dir), (std::map<std::string, std::string>{{"a.txt", "old a"}, {"b.txt", "old b"}}));
}

TEST(OutputSet, NextStartFinishesACommittedStaging) {
  fs::path dir = testutil::testDir();
  std::ofstream(dir / "a.txt") << "new a";  // moved before the kill
  std::ofstream(dir / "b.txt") << "old b";
  fakeStaging(dir, true, {"b.txt"});
  hr::OutputSet next(dir.string(), {"c.txt"});  // any run that writes here settles the folder first
  EXPECT_EQ(files(dir), (std::map<std::string, std::string>{{"a.txt", "new a"}, {"b.txt", "new b"}}));
}

TEST(OutputSet, ALiveRunsStagingIsLeftAlone) {
  fs::path dir = testutil::testDir();
  fs::path st = dir / (".ghr-staging-" + std::to_string(::getppid()));
  fs::create_directories(st);
  hr::recoverOutputs(dir.string());
  EXPECT_TRUE(fs::exists(st));
}

// ---- the kill test ------------------------------------------------------------------------------

struct Child {
  pid_t pid = -1;
  int err = -1;  // read end of the child's stderr
};

Child spawn(const std::vector<std::string>& args) {
  int fds[2];
  if (::pipe(fds) != 0) return {};
  pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(fds[1], 2);
    ::close(fds[0]);
    ::close(fds[1]);
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ::close(fds[1]);
  return {pid, fds[0]};
}

std::vector<std::string> solveArgs(const fs::path& out, int seed) {
  return {GHR_BINARY, "solve", "-o", out.string(), "--eps", "1e-3", "--threads", "1", "--seed", std::to_string(seed)};
}

/// Reads the child's stderr until a line holds what (true) or the stream ends (false).
bool waitFor(int fd, const std::string& what) {
  std::string seen;
  char buf[256];
  for (ssize_t n; (n = ::read(fd, buf, sizeof buf)) > 0;) {
    seen.append(buf, std::size_t(n));
    if (seen.find(what) != std::string::npos) return true;
  }
  return false;
}

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Which run a file came from: 1 or 2 (by the bytes of the complete runs; stats.json by its seed,
/// since it holds timings), 0 if neither.
int origin(const std::string& name, const std::string& bytes, const std::map<std::string, std::string> ref[3]) {
  if (name == "stats.json") {
    auto j = nlohmann::json::parse(bytes, nullptr, false);
    return j.is_object() && j.contains("seed") ? int(j["seed"].get<int>()) : 0;
  }
  for (int k = 1; k <= 2; ++k)
    if (ref[k].count(name) && ref[k].at(name) == bytes) return k;
  return 0;
}

TEST(OutputSetKill, SigkillDuringSolveAndWritingNeverLeavesAMix) {
  const fs::path dir = testutil::testDir(), out = dir / "out";
  std::map<std::string, std::string> ref[3];
  double total = 0.0, writing = 0.0;
  for (int seed = 1; seed <= 2; ++seed) {
    auto t0 = std::chrono::steady_clock::now();
    Child c = spawn(solveArgs(dir / ("ref" + std::to_string(seed)), seed));
    ASSERT_GT(c.pid, 0);
    ASSERT_TRUE(waitFor(c.err, "writing outputs"));
    auto tw = std::chrono::steady_clock::now();
    int status = 0;
    ::waitpid(c.pid, &status, 0);
    ::close(c.err);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    total = std::max(total, seconds(t0));
    writing = std::max(writing, seconds(tw));
    ref[seed] = files(dir / ("ref" + std::to_string(seed)));
  }
  ASSERT_EQ(ref[1].size(), ref[2].size());
  ASSERT_NE(ref[1]["solution.ghrs"], ref[2]["solution.ghrs"]) << "the two seeds must give different files";
  fs::copy(dir / "ref1", out);
  int current = 1, kept = 0, replaced = 0;
  std::mt19937 rng(12);
  for (int run = 0; run < 20; ++run) {
    const int next = 3 - current;
    Child c = spawn(solveArgs(out, next));
    ASSERT_GT(c.pid, 0);
    double delay;
    if (run % 2 == 0) {
      delay = std::uniform_real_distribution<double>(0.0, 1.1 * total)(rng);  // anywhere in the run
    } else {
      waitFor(c.err, "writing outputs");  // while the outputs are written and moved into place
      delay = std::uniform_real_distribution<double>(0.0, 1.2 * writing)(rng);
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(delay));
    ::kill(c.pid, SIGKILL);
    int status = 0;
    ::waitpid(c.pid, &status, 0);
    ::close(c.err);
    hr::recoverOutputs(out.string());  // what the next run does first
    auto now = files(out);
    std::set<int> from;
    for (const auto& [name, bytes] : now) {
      ASSERT_TRUE(ref[1].count(name)) << "run " << run << ": unexpected file " << name << " (staging or temporary left?)";
      from.insert(origin(name, bytes, ref));
    }
    ASSERT_EQ(now.size(), ref[1].size()) << "run " << run << ": a file is missing";
    ASSERT_EQ(from.size(), 1u) << "run " << run << ": a mix of two runs' files";
    ASSERT_NE(*from.begin(), 0) << "run " << run << ": a file from neither run";
    (*from.begin() == current ? kept : replaced)++;
    current = *from.begin();
  }
  std::printf("kill test: 20 runs, previous set kept %d times, new set complete %d times (run %.2f s, writing %.2f s)\n",
              kept, replaced, total, writing);
}

}  // namespace
